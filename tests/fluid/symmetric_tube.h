#pragma once
// A quasi-1-D tube [0,1] x w x w of Nx hexahedra, each split into 6 tetrahedra around a
// diagonal that is mirrored in x from one column to the next. Every node then has an
// x-symmetric element patch, so the lumped mass sits at the node: with the plain extruded
// tube (same split in every column, cases/fluid/tube.geo) every node is on the boundary and
// its patch is lopsided (3/4 of its lumped mass on one side), which makes the lumped-mass
// scheme only first-order consistent for smooth convected waves. Groups as tube.geo:
// "left", "right", "sides".
#include <algorithm>
#include <array>
#include <map>
#include <string>

#include "shellflow/mesh/mesh.h"

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
      const Vec3 x0 = m.nodes[std::size_t(t[0])];
      const double vol = (m.nodes[std::size_t(t[1])] - x0)
                             .dot((m.nodes[std::size_t(t[2])] - x0).cross(m.nodes[std::size_t(t[3])] - x0));
      if (vol < 0) std::swap(t[2], t[3]);
      m.cells.connectivity.insert(m.cells.connectivity.end(), t.begin(), t.end());
    }
  // Boundary faces: faces of exactly one tetrahedron, grouped by position.
  std::map<std::array<Index, 3>, int> count;
  static constexpr int faces[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  for (Index e = 0; e < m.num_cells(); ++e)
    for (const auto& f : faces) {
      const auto c = m.cells.element(e);
      std::array<Index, 3> key{c[std::size_t(f[0])], c[std::size_t(f[1])], c[std::size_t(f[2])]};
      std::sort(key.begin(), key.end());
      ++count[key];
    }
  for (const char* name : {"left", "right", "sides"}) {
    mesh::PhysicalGroup g;
    g.name = name;
    g.dim = 2;
    g.elements.type = mesh::ElementType::tri3;
    m.groups.push_back(g);
  }
  for (const auto& [key, n] : count) {
    if (n != 1) continue;
    auto on = [&](double x) {
      return std::all_of(key.begin(), key.end(),
                         [&](Index a) { return std::abs(m.nodes[std::size_t(a)].x() - x) < 1e-12; });
    };
    auto& g = m.groups[on(0.0) ? 0 : on(1.0) ? 1 : 2];
    g.elements.connectivity.insert(g.elements.connectivity.end(), key.begin(), key.end());
  }
  for (auto& g : m.groups) {
    g.nodes = g.elements.connectivity;
    std::sort(g.nodes.begin(), g.nodes.end());
    g.nodes.erase(std::unique(g.nodes.begin(), g.nodes.end()), g.nodes.end());
  }
  return m;
}

}  // namespace shellflow::fluid::test_support
