#pragma once
// A one-layer slab [0, lx] x [0, ly] x [0, dz] of nx x ny hexahedra, each split into 6
// tetrahedra around its main diagonal (Kuhn), like the panel-flutter slab: every node lies
// on one of the symmetry planes z = 0, dz. Groups "left" (x = 0), "right" (x = lx),
// "bottom" (y = 0), "top" (y = ly), "symmetry" (z = 0 and z = dz).
#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "shellflow/mesh/mesh.h"

namespace shellflow::fluid::test_support {

inline mesh::Mesh slab_mesh(int nx, int ny, double lx, double ly, double dz) {
  mesh::Mesh m;
  m.name = "slab";
  auto id = [&](int i, int j, int k) { return Index(i + (nx + 1) * (j + (ny + 1) * k)); };
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) m.nodes.emplace_back(lx * i / nx, ly * j / ny, dz * k);
  m.cells.type = mesh::ElementType::tet4;
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      for (const auto& p : perms) {
        std::array<int, 3> c{i, j, 0};
        std::array<Index, 4> t{};
        t[0] = id(c[0], c[1], c[2]);
        for (int s = 0; s < 3; ++s) {
          ++c[std::size_t(p[s])];
          t[std::size_t(s + 1)] = id(c[0], c[1], c[2]);
        }
        const Vec3 x0 = m.nodes[std::size_t(t[0])];
        const double vol = (m.nodes[std::size_t(t[1])] - x0)
                               .dot((m.nodes[std::size_t(t[2])] - x0).cross(m.nodes[std::size_t(t[3])] - x0));
        if (vol < 0) std::swap(t[2], t[3]);
        m.cells.connectivity.insert(m.cells.connectivity.end(), t.begin(), t.end());
      }
  // Boundary faces: faces of exactly one tetrahedron, grouped by the plane they lie on.
  std::map<std::array<Index, 3>, int> count;
  static constexpr int faces[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  for (Index e = 0; e < m.num_cells(); ++e)
    for (const auto& f : faces) {
      const auto c = m.cells.element(e);
      std::array<Index, 3> key{c[std::size_t(f[0])], c[std::size_t(f[1])], c[std::size_t(f[2])]};
      std::sort(key.begin(), key.end());
      ++count[key];
    }
  for (const char* name : {"left", "right", "bottom", "top", "symmetry"}) {
    mesh::PhysicalGroup g;
    g.name = name;
    g.dim = 2;
    g.elements.type = mesh::ElementType::tri3;
    m.groups.push_back(g);
  }
  for (const auto& [key, n] : count) {
    if (n != 1) continue;
    auto on = [&](int axis, double value) {
      return std::all_of(key.begin(), key.end(), [&](Index a) {
        return std::abs(m.nodes[std::size_t(a)][axis] - value) < 1e-12;
      });
    };
    const int g = on(0, 0.0) ? 0 : on(0, lx) ? 1 : on(1, 0.0) ? 2 : on(1, ly) ? 3 : 4;
    auto& conn = m.groups[std::size_t(g)].elements.connectivity;
    conn.insert(conn.end(), key.begin(), key.end());
  }
  for (auto& g : m.groups) {
    g.nodes = g.elements.connectivity;
    std::sort(g.nodes.begin(), g.nodes.end());
    g.nodes.erase(std::unique(g.nodes.begin(), g.nodes.end()), g.nodes.end());
  }
  return m;
}

}  // namespace shellflow::fluid::test_support
