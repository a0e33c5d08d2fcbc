#pragma once
// The one structured tetrahedral box of the tests and benchmarks: [0, L.x] x [0, L.y] x
// [0, L.z] in n.x * n.y * n.z cubes, each split into the 6 tetrahedra around its main
// diagonal (Kuhn; the same split everywhere, so faces match), boundary triangles grouped by a
// function of their centroid. Built in code, so that 10^6 tetrahedra cost no meshing time.
#include <algorithm>
#include <array>
#include <functional>
#include <map>
#include <string>

#include "shellflow/mesh/mesh.h"

namespace shellflow::support {

/// Appends tetrahedron t to m, its vertices ordered for a positive volume.
inline void add_tet(mesh::Mesh& m, std::array<Index, 4> t) {
  const Vec3 x0 = m.nodes[std::size_t(t[0])];
  const double vol =
      (m.nodes[std::size_t(t[1])] - x0).dot((m.nodes[std::size_t(t[2])] - x0).cross(m.nodes[std::size_t(t[3])] - x0));
  if (vol < 0) std::swap(t[2], t[3]);
  m.cells.connectivity.insert(m.cells.connectivity.end(), t.begin(), t.end());
}

/// The boundary triangles of a tetrahedral mesh (faces of one tetrahedron only) into the
/// groups group_of(face centroid) names, in the order the names are first met; "" leaves a
/// face out of every group.
inline void group_boundary_faces(mesh::Mesh& m, const std::function<std::string(const Vec3&)>& group_of) {
  std::map<std::array<Index, 3>, int> count;
  static constexpr int faces[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  for (Index e = 0; e < m.num_cells(); ++e)
    for (const auto& f : faces) {
      const auto c = m.cells.element(e);
      std::array<Index, 3> key{c[std::size_t(f[0])], c[std::size_t(f[1])], c[std::size_t(f[2])]};
      std::sort(key.begin(), key.end());
      ++count[key];
    }
  std::map<std::string, std::size_t> slot;
  for (const auto& [key, times] : count) {
    if (times != 1) continue;
    Vec3 centroid = Vec3::Zero();
    for (const Index a : key) centroid += m.nodes[std::size_t(a)] / 3.0;
    const std::string name = group_of(centroid);
    if (name.empty()) continue;
    if (!slot.contains(name)) {
      slot[name] = m.groups.size();
      mesh::PhysicalGroup g;
      g.name = name;
      g.dim = 2;
      g.elements.type = mesh::ElementType::tri3;
      m.groups.push_back(g);
    }
    auto& conn = m.groups[slot[name]].elements.connectivity;
    conn.insert(conn.end(), key.begin(), key.end());
  }
  for (auto& g : m.groups) {
    g.nodes = g.elements.connectivity;
    std::sort(g.nodes.begin(), g.nodes.end());
    g.nodes.erase(std::unique(g.nodes.begin(), g.nodes.end()), g.nodes.end());
  }
}

/// Box [0, L.x] x [0, L.y] x [0, L.z] of n.x * n.y * n.z cubes, each split into the 6
/// tetrahedra around its main diagonal (the same split everywhere, so faces match).
/// Boundary triangles go to the group group_of(face centroid) names; "" leaves them out of
/// every group (no condition: used for the faces tied periodically by PeriodicTie).
inline mesh::Mesh box_mesh(std::array<int, 3> n, const Vec3& L,
                           const std::function<std::string(const Vec3&)>& group_of) {
  mesh::Mesh m;
  m.name = "box";
  auto id = [&](int i, int j, int k) { return Index(i + (n[0] + 1) * (j + (n[1] + 1) * k)); };
  for (int k = 0; k <= n[2]; ++k)
    for (int j = 0; j <= n[1]; ++j)
      for (int i = 0; i <= n[0]; ++i) m.nodes.emplace_back(L.x() * i / n[0], L.y() * j / n[1], L.z() * k / n[2]);
  m.cells.type = mesh::ElementType::tet4;
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i)
        for (const auto& p : perms) {
          std::array<int, 3> c{i, j, k};
          std::array<Index, 4> t{};
          t[0] = id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[std::size_t(p[s])];
            t[std::size_t(s + 1)] = id(c[0], c[1], c[2]);
          }
          add_tet(m, t);
        }
  group_boundary_faces(m, group_of);
  return m;
}

}  // namespace shellflow::support
