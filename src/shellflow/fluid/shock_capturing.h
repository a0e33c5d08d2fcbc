#pragma once
// Pressure-switch artificial viscosity (paper eqs. 27–28, fluid.md §7):
//   nu_e = q_dif h_e^3 (|u|_e + c_e) / p_e |lap p|_e,
// with lap p recovered from a lumped projection of the element pressure gradients and,
// by default, smoothed over one element layer (nodal volume average, then element mean).
#include <array>
#include <functional>
#include <span>
#include <vector>

#include "shellflow/fluid/gas.h"
#include "shellflow/fluid/geometry.h"
#include "shellflow/fluid/residual.h"
#include "shellflow/fluid/state.h"

namespace shellflow::fluid {

struct ShockCapturingWorkspace {
  std::vector<double> pressure;                 // nodal p
  std::vector<double> speed;                    // nodal |u| + c
  std::array<std::vector<double>, 3> gradient;  // recovered nodal grad p
  std::vector<double> nodal_viscosity;          // sum V_e nu_e, then nu_a
};

/// Sets the ghost-node entries of nodal fields from their owners (a rank's part of a
/// distributed mesh, docs/parallel.md); empty in one process.
using GhostExchange = std::function<void(std::span<double* const> fields)>;

/// Element artificial viscosities for state u (zero everywhere when q_dif = 0). On a rank's
/// part, `exchange` makes the recovered nodal gradient and the smoothed nodal viscosity those
/// of the owners before elements use them.
void compute_artificial_viscosity(const IdealGas& gas, double q_dif, bool smoothing, const ElementLoop& loop,
                                  const TetGeometry& geometry, const FluidState& u, ShockCapturingWorkspace& work,
                                  std::vector<double>& element_viscosity, const GhostExchange& exchange = {});

}  // namespace shellflow::fluid
