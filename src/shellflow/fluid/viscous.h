#pragma once
// Navier–Stokes viscous and conduction terms (fluid.md §1, §4.2, §13): a separate element
// pass over the tetrahedra that adds -Δt V_e B_{a,j} G_{j,e} to the first-order rows of the
// residual (they stay out of the Taylor–Galerkin term). G_j = (0, tau_ij, tau_ij ū_i +
// k dT/dx_j) with element velocity and temperature gradients, the element-mean velocity ū_e
// and mu at the element-mean temperature. Inviscid runs never call it, so the Euler step
// costs nothing extra. Gradients are formed from differences to the element's first node
// (fluid.md §11): a uniform state gives exactly zero fluxes.
#include <array>
#include <span>
#include <vector>

#include "shellflow/core/types.h"
#include "shellflow/fluid/element_loop.h"
#include "shellflow/fluid/gas.h"
#include "shellflow/fluid/geometry.h"
#include "shellflow/fluid/residual.h"
#include "shellflow/fluid/state.h"

namespace shellflow::fluid {

/// Throws InputError naming the parameter when a viscous law has a non-positive mu_ref,
/// t_ref or Prandtl number, or a negative Sutherland constant.
void check_viscosity(const IdealGas& gas);

/// Viscous fluxes of one tetrahedron (constant in a P1 element).
struct ElementViscousFlux {
  Mat3 stress = Mat3::Zero();         ///< tau_ij = mu (du_i/dx_j + du_j/dx_i - 2/3 delta_ij div u)
  Vec3 conduction = Vec3::Zero();     ///< k grad T (minus the Fourier heat flux)
  Vec3 mean_velocity = Vec3::Zero();  ///< ū_e, mean of the nodal velocities
  double viscosity = 0.0;             ///< mu at the element-mean temperature
  /// Energy-row flux G_j = tau_ij ū_i + k dT/dx_j.
  Vec3 energy_flux() const { return stress.transpose() * mean_velocity + conduction; }
};

/// Fluxes of the element with nodes `nodes` (4) and shape-function gradients `grad`
/// (B_a,j at [3 a + j]) for the nodal state u.
ElementViscousFlux element_viscous_flux(const IdealGas& gas, const Index* nodes, const double* grad,
                                        const FluidState& u);

/// Nodal velocity and temperature (u_x, u_y, u_z, T), computed once per node so that the
/// element pass gathers one 32-byte record per node and divides nothing.
using NodalVelocityTemperature = std::vector<std::array<double, 4>>;

/// Adds the viscous and conduction terms to r: node a of element e receives
/// -Δt_a V_e B_{a,j} G_{j,e} (rows 1-4; the mass row has no viscous flux). `nodal_dt`
/// empty: the global dt; otherwise the local steps of a steady run (fluid.md §4.3).
/// `work`: scratch for the nodal velocity and temperature.
void add_viscous_residual(const IdealGas& gas, double dt, std::span<const double> nodal_dt, const ElementLoop& loop,
                          const TetGeometry& geometry, const FluidState& u, FluidState& r,
                          NodalVelocityTemperature& work);

/// Adds the work of the viscous stress on adiabatic no-slip walls to the energy row: with no
/// heat flux the energy flux through the wall is tau_ij u_i n_j, nonzero when the wall moves
/// tangentially. Node a of face f receives Δt_a ∫_f N_a tau_ij u_i n_j dA, tau of the owning
/// element, u linear on the face.
void add_wall_work(const IdealGas& gas, double dt, std::span<const double> nodal_dt, std::span<const Index> tets,
                   std::span<const Vec3> x, const TetGeometry& geometry, const FluidState& u,
                   std::span<const BoundaryFace> faces, FluidState& r);

/// Element diffusivities for the time-step limit h^2 / (2 nu): out_e = artificial_e (may
/// be empty) + max(mu, gamma mu / Pr) / rho at the element means (fluid.md §8).
void element_diffusivity(const IdealGas& gas, std::span<const Index> tets, const FluidState& u,
                         std::span<const double> artificial, std::vector<double>& out);

}  // namespace shellflow::fluid
