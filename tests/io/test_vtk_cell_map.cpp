// Gmsh -> VTK cell mapping: the writer's reference tables are checked against the Gmsh API
// (Gmsh side) and against VTK's ordering rule restated here (VTK side); the permutations
// are checked by position and against the known answers.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <numeric>
#include <vector>

#include "io_test_util.h"
#include "shellflow/core/error.h"
#include "shellflow/io/vtu_writer.h"

namespace shellflow::io {
namespace {

const std::vector<int> kTypes = {15, 1, 8, 26, 2, 9, 21, 4, 11, 29};

TEST(VtkCellMap, GmshReferenceNodesMatchTheGmshApi) {
  for (int type : kTypes) {
    SCOPED_TRACE("Gmsh type " + std::to_string(type));
    const std::vector<double> expected = test::gmsh_api_reference_nodes(type);
    const auto ref = gmsh_reference_nodes(type);
    ASSERT_EQ(expected.size(), 3u * static_cast<std::size_t>(gmsh_nodes_per_cell(type)));
    ASSERT_EQ(ref.size(), expected.size());
    for (std::size_t i = 0; i < ref.size(); ++i) {
      EXPECT_NEAR(ref[i], expected[i], 1e-14) << "node " << i / 3 << " coordinate " << i % 3;
    }
  }
}

// VTK's ordering of a simplex cell of order p (vtkQuadraticEdge/Triangle/Tetra,
// vtkHigherOrderCurve/Triangle/Tetra): vertices; p-1 points on each edge, walking from the
// edge's first vertex to its second, edges (0,1) (1,2) (2,0) (0,3) (1,3) (2,3); for p = 3
// one point at the centroid of each face (0,1,3) (1,2,3) (2,0,3) (0,2,1) of a tetrahedron,
// or at the triangle's centroid. Lines run over [0, 1] with interior points increasing.
std::vector<std::array<double, 3>> vtk_rule(int dim, int p) {
  using Point = std::array<double, 3>;
  using Edge = std::array<std::size_t, 2>;
  const std::array<Point, 4> v = {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  std::vector<Point> out(v.begin(), v.begin() + dim + 1);
  const std::vector<Edge> edges = dim == 1   ? std::vector<Edge>{{0, 1}}
                                  : dim == 2 ? std::vector<Edge>{{0, 1}, {1, 2}, {2, 0}}
                                  : dim == 3 ? std::vector<Edge>{{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}}
                                             : std::vector<Edge>{};
  for (const auto& e : edges) {
    for (int k = 1; k < p; ++k) {
      const double t = static_cast<double>(k) / p;
      Point x{};
      for (std::size_t a = 0; a < 3; ++a) x[a] = (1 - t) * v[e[0]][a] + t * v[e[1]][a];
      out.push_back(x);
    }
  }
  if (p == 3 && dim == 2) out.push_back({1.0 / 3, 1.0 / 3, 0});
  if (p == 3 && dim == 3) {
    const std::array<std::array<std::size_t, 3>, 4> faces = {{{0, 1, 3}, {1, 2, 3}, {2, 0, 3}, {0, 2, 1}}};
    for (const auto& f : faces) {
      Point x{};
      for (std::size_t a = 0; a < 3; ++a) x[a] = (v[f[0]][a] + v[f[1]][a] + v[f[2]][a]) / 3.0;
      out.push_back(x);
    }
  }
  return out;
}

TEST(VtkCellMap, VtkReferenceNodesFollowVtkOrdering) {
  struct Case {
    int gmsh_type, dim, order;
  };
  for (const Case c : {Case{15, 0, 0}, Case{1, 1, 1}, Case{8, 1, 2}, Case{26, 1, 3}, Case{2, 2, 1}, Case{9, 2, 2},
                       Case{21, 2, 3}, Case{4, 3, 1}, Case{11, 3, 2}, Case{29, 3, 3}}) {
    SCOPED_TRACE("Gmsh type " + std::to_string(c.gmsh_type));
    const auto expected = vtk_rule(c.dim, c.order);
    const auto ref = vtk_reference_nodes(c.gmsh_type);
    ASSERT_EQ(ref.size(), 3 * expected.size());
    for (std::size_t i = 0; i < expected.size(); ++i) {
      for (std::size_t a = 0; a < 3; ++a) {
        EXPECT_NEAR(ref[3 * i + a], expected[i][a], 1e-14) << "VTK node " << i;
      }
    }
  }
}

TEST(VtkCellMap, PermutationPutsEveryVtkNodeOnItsGmshNode) {
  for (int type : kTypes) {
    SCOPED_TRACE("Gmsh type " + std::to_string(type));
    const auto perm = gmsh_to_vtk_permutation(type);
    const auto n = static_cast<std::size_t>(gmsh_nodes_per_cell(type));
    ASSERT_EQ(perm.size(), n);
    std::vector<int> sorted(perm.begin(), perm.end());
    std::sort(sorted.begin(), sorted.end());
    std::vector<int> iota(n);
    std::iota(iota.begin(), iota.end(), 0);
    EXPECT_EQ(sorted, iota) << "not a permutation";
    const bool line = type == 1 || type == 8 || type == 26;
    const auto g = gmsh_reference_nodes(type);
    const auto v = vtk_reference_nodes(type);
    for (std::size_t i = 0; i < n; ++i) {
      const auto j = static_cast<std::size_t>(perm[i]);
      for (std::size_t a = 0; a < 3; ++a) {
        const double gx = line && a == 0 ? 0.5 * (g[3 * j] + 1.0) : g[3 * j + a];
        EXPECT_NEAR(gx, v[3 * i + a], 1e-14) << "VTK node " << i << " <- Gmsh node " << j;
      }
    }
  }
}

TEST(VtkCellMap, KnownPermutations) {
  auto perm = [](int type) {
    const auto p = gmsh_to_vtk_permutation(type);
    return std::vector<int>(p.begin(), p.end());
  };
  auto identity = [](int n) {
    std::vector<int> v(static_cast<std::size_t>(n));
    std::iota(v.begin(), v.end(), 0);
    return v;
  };
  for (int type : {15, 1, 8, 26, 2, 9, 21, 4}) {
    EXPECT_EQ(perm(type), identity(gmsh_nodes_per_cell(type))) << "Gmsh type " << type;
  }
  EXPECT_EQ(perm(11), (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7, 9, 8}));
  EXPECT_EQ(perm(29), (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 11, 10, 15, 14, 13, 12, 17, 19, 18, 16}));
}

TEST(VtkCellMap, VtkCellTypes) {
  const std::vector<std::pair<int, int>> expected = {{15, 1}, {1, 3},   {8, 21}, {26, 68}, {2, 5},
                                                     {9, 22}, {21, 69}, {4, 10}, {11, 24}, {29, 71}};
  for (const auto& [gmsh, vtk] : expected) {
    EXPECT_TRUE(is_vtu_supported_type(gmsh));
    EXPECT_EQ(vtk_cell_type(gmsh), vtk) << "Gmsh type " << gmsh;
  }
}

TEST(VtkCellMap, UnsupportedTypeIsAnInputError) {
  EXPECT_FALSE(is_vtu_supported_type(3));  // 4-node quadrangle
  EXPECT_THROW(vtk_cell_type(3), InputError);
  EXPECT_THROW(gmsh_to_vtk_permutation(5), InputError);
}

}  // namespace
}  // namespace shellflow::io
