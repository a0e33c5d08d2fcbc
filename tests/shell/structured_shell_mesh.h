#pragma once
// A structured Tri10 shell mesh of the parameter rectangle [0, L] x [0, W] mapped through
// any smooth surface map (tests only): plane, rotated plane, cylinder. Groups: lines
// "left" (s = 0), "right" (s = L), "bottom" (t = 0), "top" (t = W) of 4-node lines, and
// the surface group "shell" holding every cell.
#include <algorithm>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "shellflow/fem/shape_functions.h"
#include "shellflow/mesh/mesh.h"

namespace shellflow::shell::testing {

inline mesh::Mesh structured_shell_mesh(double L, double W, int nx, int ny,
                                        const std::function<Vec3(double, double)>& map,
                                        std::string source = "structured") {
  mesh::Mesh m;
  m.name = "shell";
  m.source = std::move(source);
  m.cells.type = mesh::ElementType::tri10;
  // Nodes on the lattice (3 nx + 1) x (3 ny + 1).
  const int ni = 3 * nx + 1, nj = 3 * ny + 1;
  std::vector<Index> id(static_cast<std::size_t>(ni * nj), -1);
  const auto node = [&](int i, int j) {
    Index& n = id[static_cast<std::size_t>(j * ni + i)];
    if (n < 0) {
      n = static_cast<Index>(m.nodes.size());
      m.nodes.push_back(map(L * i / (ni - 1), W * j / (nj - 1)));
      m.node_tags.push_back(m.nodes.size());
    }
    return n;
  };
  const auto& points = fem::Tri10::node_points;
  const auto add_triangle = [&](std::array<int, 2> v0, std::array<int, 2> v1, std::array<int, 2> v2) {
    for (const auto& p : points) {
      const int i = v0[0] + static_cast<int>(std::lround(p[0] * (v1[0] - v0[0]) + p[1] * (v2[0] - v0[0])));
      const int j = v0[1] + static_cast<int>(std::lround(p[0] * (v1[1] - v0[1]) + p[1] * (v2[1] - v0[1])));
      m.cells.connectivity.push_back(node(i, j));
    }
  };
  for (int cy = 0; cy < ny; ++cy)
    for (int cx = 0; cx < nx; ++cx) {
      const int i = 3 * cx, j = 3 * cy;
      add_triangle({i, j}, {i + 3, j}, {i + 3, j + 3});
      add_triangle({i, j}, {i + 3, j + 3}, {i, j + 3});
    }
  // Boundary lines: Line4 order is vertex 0, vertex 1, then the points at 1/3 and 2/3.
  const auto line_group = [&](const std::string& name, int tag, auto lattice, int count) {
    mesh::PhysicalGroup g;
    g.name = name;
    g.dim = 1;
    g.tag = tag;
    g.elements.type = mesh::ElementType::line4;
    for (int k = 0; k < count; ++k)
      for (int o : {0, 3, 1, 2}) {
        const auto [i, j] = lattice(3 * k + o);
        g.elements.connectivity.push_back(node(i, j));
      }
    g.nodes = g.elements.connectivity;
    std::sort(g.nodes.begin(), g.nodes.end());
    g.nodes.erase(std::unique(g.nodes.begin(), g.nodes.end()), g.nodes.end());
    m.groups.push_back(std::move(g));
  };
  line_group(
      "left", 1,
      [](int k) {
        return std::pair{0, k};
      },
      ny);
  line_group(
      "right", 2,
      [&](int k) {
        return std::pair{ni - 1, k};
      },
      ny);
  line_group(
      "bottom", 3,
      [](int k) {
        return std::pair{k, 0};
      },
      nx);
  line_group(
      "top", 4,
      [&](int k) {
        return std::pair{k, nj - 1};
      },
      nx);
  mesh::PhysicalGroup surface;
  surface.name = "shell";
  surface.dim = 2;
  surface.tag = 5;
  for (Index e = 0; e < m.num_cells(); ++e) surface.cells.push_back(e);
  for (Index n = 0; n < m.num_nodes(); ++n) surface.nodes.push_back(n);
  m.groups.push_back(std::move(surface));
  return m;
}

}  // namespace shellflow::shell::testing
