#pragma once
// Stable explicit time step (fluid.md §8): dt_e = min(h_e / (|u - w|_e + c_e),
// h_e^2 / (2 nu_e)); the global step is CFL * min_e dt_e.
#include <array>
#include <span>
#include <vector>

#include "shellflow/fluid/gas.h"
#include "shellflow/fluid/geometry.h"
#include "shellflow/fluid/state.h"

namespace shellflow::fluid {

/// min over elements of dt_e (CFL = 1). `w`: mesh velocity of the previous step;
/// `element_viscosity`: artificial viscosity (may be empty).
/// `nodal_work`: scratch (relative velocity and sound speed per node); `element_dt`, when
/// given, receives every dt_e (for local time stepping).
double min_element_time_step(const IdealGas& gas, std::span<const Index> tets, const TetGeometry& geometry,
                             const FluidState& u, std::span<const Vec3> w, std::span<const double> element_viscosity,
                             std::vector<std::array<double, 4>>& nodal_work, std::vector<double>* element_dt = nullptr);

}  // namespace shellflow::fluid
