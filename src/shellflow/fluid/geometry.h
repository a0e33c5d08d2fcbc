#pragma once
// Per-tetrahedron geometry of the current configuration (volume, constant shape-function
// gradients, size) and the lumped mass. Recomputed after every mesh motion.
#include <array>
#include <span>
#include <vector>

#include "shellflow/core/types.h"
#include "shellflow/fluid/element_loop.h"

namespace shellflow::fluid {

struct TetGeometry {
  std::vector<double> volume;                ///< V_e
  std::vector<std::array<double, 12>> grad;  ///< B_a = grad N_a, stored [3 a + j], a = 0..3
  std::vector<double> size;                  ///< h_e = 3 V_e / largest face area
  std::vector<double> lumped_mass;           ///< M_a = sum over e of V_e / 4, per node

  Index num_elements() const { return static_cast<Index>(volume.size()); }
};

/// Fills `geometry` for the 4-node tetrahedra `tets` (flat connectivity) at positions `x`.
/// Throws SolverError naming the element and its nodes when a volume is not positive
/// (inverted or degenerate element after a mesh update).
void compute_geometry(std::span<const Vec3> x, std::span<const Index> tets, TetGeometry& geometry);
/// The same for the elements of a colour-ordered loop (`loop.tets`): the lumped mass is
/// scattered colour by colour in parallel, with the same bits as the serial sum (every node
/// gets its elements' shares in element order either way).
void compute_geometry(std::span<const Vec3> x, const ElementLoop& loop, TetGeometry& geometry);

}  // namespace shellflow::fluid
