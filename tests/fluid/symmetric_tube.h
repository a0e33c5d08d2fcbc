#pragma once
// A quasi-1-D tube [0,1] x w x w of Nx hexahedra, each split into 6 tetrahedra around a
// diagonal that is mirrored in x from one column to the next. Every node then has an
// x-symmetric element patch, so the lumped mass sits at the node: with the plain extruded
// tube (same split in every column, cases/fluid/tube.geo) every node is on the boundary and
// its patch is lopsided (3/4 of its lumped mass on one side), which makes the lumped-mass
// scheme only first-order consistent for smooth convected waves. Groups as tube.geo:
// "left", "right", "sides".
#include <array>
#include <cmath>
#include <string>

#include "shellflow/mesh/mesh.h"
#include "support/box_mesh.h"

namespace shellflow::fluid::test_support {

inline mesh::Mesh symmetric_tube(int nx, double width) {
  mesh::Mesh m;
  m.name = "tube";
  auto id = [](int i, int j, int k) { return Index(4 * i + 2 * k + j); };
  for (int i = 0; i <= nx; ++i)
    for (int k = 0; k < 2; ++k)
      for (int j = 0; j < 2; ++j) m.nodes.emplace_back(double(i) / nx, j * width, k * width);
  m.cells.type = mesh::ElementType::tet4;
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int i = 0; i < nx; ++i)
    for (const auto& p : perms) {
      std::array<int, 3> bits{0, 0, 0};
      std::array<Index, 4> t{};
      auto node = [&] {
        const int bx = (i % 2 == 1) ? 1 - bits[0] : bits[0];  // mirrored split in odd columns
        return id(i + bx, bits[1], bits[2]);
      };
      t[0] = node();
      for (int s = 0; s < 3; ++s) {
        bits[std::size_t(p[s])] = 1;
        t[std::size_t(s + 1)] = node();
      }
      support::add_tet(m, t);
    }
  // Boundary faces grouped by position.
  support::group_boundary_faces(m, [](const Vec3& c) -> std::string {
    return std::abs(c.x()) < 1e-12 ? "left" : std::abs(c.x() - 1.0) < 1e-12 ? "right" : "sides";
  });
  return m;
}

}  // namespace shellflow::fluid::test_support
