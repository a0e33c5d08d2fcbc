#pragma once
// Structured unit-cube meshes for the benchmarks: n^3 cubes, each split into 6 tetrahedra
// around its main diagonal (Kuhn), with boundary groups "inflow" (x = 0), "outflow"
// (x = 1), "walls" (y = 0, 1) and "symmetry" (z = 0, 1). Built in code so that 10^6
// tetrahedra cost no meshing time.
#include <algorithm>
#include <array>
#include <string>

#include "shellflow/mesh/mesh.h"

namespace shellflow::fluid::bench {

inline mesh::Mesh box_mesh(int n) {
  mesh::Mesh m;
  m.name = "box";
  const int np = n + 1;
  auto id = [np](int i, int j, int k) { return Index(i + np * (j + np * k)); };
  for (int k = 0; k < np; ++k)
    for (int j = 0; j < np; ++j)
      for (int i = 0; i < np; ++i) m.nodes.emplace_back(double(i) / n, double(j) / n, double(k) / n);
  m.cells.type = mesh::ElementType::tet4;
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (const auto& p : perms) {
          std::array<int, 3> c{i, j, k};
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
  const char* names[3][2] = {{"inflow", "outflow"}, {"walls", "walls"}, {"symmetry", "symmetry"}};
  for (const char* name : {"inflow", "outflow", "walls", "symmetry"}) {
    mesh::PhysicalGroup g;
    g.name = name;
    g.dim = 2;
    g.elements.type = mesh::ElementType::tri3;
    m.groups.push_back(g);
  }
  auto group = [&](const char* name) -> mesh::PhysicalGroup& {
    return *std::find_if(m.groups.begin(), m.groups.end(), [&](auto& g) { return g.name == name; });
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      auto& g = group(names[axis][side]);
      const int a = (axis + 1) % 3, b = (axis + 2) % 3;
      for (int q = 0; q < n; ++q)
        for (int r = 0; r < n; ++r) {
          auto node = [&](int da, int db) {
            std::array<int, 3> c{};
            c[std::size_t(axis)] = side * n;
            c[std::size_t(a)] = q + da;
            c[std::size_t(b)] = r + db;
            return id(c[0], c[1], c[2]);
          };
          // The diagonal (0,0)-(1,1) matches the Kuhn tetrahedra's faces.
          for (const Index v : {node(0, 0), node(1, 0), node(1, 1), node(0, 0), node(0, 1), node(1, 1)})
            g.elements.connectivity.push_back(v);
        }
    }
  for (auto& g : m.groups) {
    g.nodes = g.elements.connectivity;
    std::sort(g.nodes.begin(), g.nodes.end());
    g.nodes.erase(std::unique(g.nodes.begin(), g.nodes.end()), g.nodes.end());
  }
  return m;
}

}  // namespace shellflow::fluid::bench
