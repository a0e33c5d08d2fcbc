#include "shellflow/fluid/geometry.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "shellflow/core/error.h"
#include "shellflow/fluid/element_loop.h"

namespace shellflow::fluid {

namespace {

/// Volumes, gradients and sizes; the lumped mass is left to the caller.
void element_geometry(std::span<const Vec3> x, std::span<const Index> tets, TetGeometry& g) {
  const auto ne = static_cast<Index>(tets.size() / 4);
  g.volume.resize(static_cast<std::size_t>(ne));
  g.grad.resize(static_cast<std::size_t>(ne));
  g.size.resize(static_cast<std::size_t>(ne));
  g.lumped_mass.assign(x.size(), 0.0);

  // The lowest-numbered inverted element, whatever the thread count.
  constexpr Index none = std::numeric_limits<Index>::max();
  const Index worst = reduce_items(
      ne, parallel::kElementGrain, parallel_threshold, none,
      [&](Index e) {
        const Index* n = tets.data() + 4 * static_cast<std::size_t>(e);
        const Vec3 x0 = x[static_cast<std::size_t>(n[0])];
        const Vec3 d1 = x[static_cast<std::size_t>(n[1])] - x0;
        const Vec3 d2 = x[static_cast<std::size_t>(n[2])] - x0;
        const Vec3 d3 = x[static_cast<std::size_t>(n[3])] - x0;
        // Rows of the inverse Jacobian are the gradients of N_1..N_3 (cofactors / det).
        const Vec3 c1 = d2.cross(d3);
        const Vec3 c2 = d3.cross(d1);
        const Vec3 c3 = d1.cross(d2);
        const double det = d1.dot(c1);
        const auto ue = static_cast<std::size_t>(e);
        g.volume[ue] = det / 6.0;
        if (!(det > 0.0)) return e;
        // One division per element (nine were a third of the geometry's time).
        const double inv_det = 1.0 / det;
        const Vec3 b1 = c1 * inv_det, b2 = c2 * inv_det, b3 = c3 * inv_det;
        const Vec3 b0 = -(b1 + b2 + b3);
        auto& b = g.grad[ue];
        const Vec3* bs[4] = {&b0, &b1, &b2, &b3};
        double max_norm2 = 0.0;
        for (int a = 0; a < 4; ++a) {
          for (int j = 0; j < 3; ++j) b[static_cast<std::size_t>(3 * a + j)] = (*bs[a])[j];
          max_norm2 = std::max(max_norm2, bs[a]->squaredNorm());
        }
        // |B_a| = A_a / (3 V): the smallest altitude is 1 / max |B_a|.
        g.size[ue] = 1.0 / std::sqrt(max_norm2);
        return none;
      },
      [](Index p, Index q) { return std::min(p, q); });
  const Index first_bad = worst == none ? -1 : worst;
  if (first_bad >= 0) {
    const Index* n = tets.data() + 4 * static_cast<std::size_t>(first_bad);
    throw SolverError(
        fmt::format("fluid element {} (nodes {} {} {} {}) has volume {:.3e} <= 0: the mesh update "
                    "inverted it; reduce the time step or the mesh deformation",
                    first_bad, n[0], n[1], n[2], n[3], g.volume[static_cast<std::size_t>(first_bad)]));
  }
}

}  // namespace

void compute_geometry(std::span<const Vec3> x, std::span<const Index> tets, TetGeometry& g) {
  element_geometry(x, tets, g);
  const auto ne = static_cast<Index>(tets.size() / 4);
  for (Index e = 0; e < ne; ++e) {
    const double quarter = 0.25 * g.volume[static_cast<std::size_t>(e)];
    for (int a = 0; a < 4; ++a)
      g.lumped_mass[static_cast<std::size_t>(tets[4 * static_cast<std::size_t>(e) + a])] += quarter;
  }
}

void compute_geometry(std::span<const Vec3> x, const ElementLoop& loop, TetGeometry& g) {
  element_geometry(x, loop.tets, g);
  for_each_element(loop, [&](Index e) {
    const auto ue = static_cast<std::size_t>(e);
    const double quarter = 0.25 * g.volume[ue];
    for (int a = 0; a < 4; ++a) g.lumped_mass[static_cast<std::size_t>(loop.tets[4 * ue + std::size_t(a)])] += quarter;
  });
}

}  // namespace shellflow::fluid
