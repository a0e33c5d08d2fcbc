#pragma once
// Mass matrices of P1 tetrahedra (fluid.md §5): the lumped mass is in TetGeometry; the
// consistent mass M_ab = V (1 + delta_ab) / 20 is applied matrix-free and inverted by a few
// Jacobi iterations preconditioned with the lumped mass.
#include <functional>

#include "shellflow/fluid/element_loop.h"
#include "shellflow/fluid/geometry.h"
#include "shellflow/fluid/state.h"

namespace shellflow::fluid {

/// out = M_C x (all five variables).
void apply_consistent_mass(const ElementLoop& loop, const TetGeometry& geometry, const FluidState& x, FluidState& out);

/// Solves M_C dx = r approximately: dx = M_L^{-1} r, then `iterations` Jacobi sweeps
/// dx += M_L^{-1} (r - M_C dx). `reimpose`, when set, overwrites the increments of
/// Dirichlet nodes after every sweep (so wrong values there do not spread). `work` is
/// scratch of the same size.
void solve_consistent_mass(const ElementLoop& loop, const TetGeometry& geometry, const FluidState& r, int iterations,
                           FluidState& dx, FluidState& work, const std::function<void(FluidState&)>& reimpose = {});

}  // namespace shellflow::fluid
