// Tests of the Laplacian-smoothing baseline mover (motion/laplace_mover.h).
#include <gtest/gtest.h>

#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>

#include "motion_test_util.h"
#include "shellflow/core/error.h"
#include "shellflow/mesh/quality.h"
#include "shellflow/motion/laplace_mover.h"

using namespace shellflow;
using namespace shellflow::motion;
using motion_test::at;
using motion_test::fluid;

namespace {

/// P1 stiffness of a tet4 mesh, assembled independently of the mover (cofactor form).
Eigen::SparseMatrix<double> stiffness(const mesh::Mesh& m) {
  std::vector<Eigen::Triplet<double>> t;
  for (Index e = 0; e < m.num_cells(); ++e) {
    const auto v = m.cells.element(e);
    Eigen::Matrix4d a;
    for (int i = 0; i < 4; ++i) {
      const Vec3& p = m.nodes[static_cast<std::size_t>(v[static_cast<std::size_t>(i)])];
      a.row(i) << 1.0, p.x(), p.y(), p.z();
    }
    // Barycentric coordinates N_i = c_i . (1, x, y, z): columns of a^{-1}.
    const Eigen::Matrix4d c = a.inverse();
    const double volume = std::abs(a.determinant()) / 6.0;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j)
        t.emplace_back(v[static_cast<std::size_t>(i)], v[static_cast<std::size_t>(j)],
                       volume * c.col(i).tail<3>().dot(c.col(j).tail<3>()));
  }
  Eigen::SparseMatrix<double> k(m.num_nodes(), m.num_nodes());
  k.setFromTriplets(t.begin(), t.end());
  return k;
}

}  // namespace

TEST(LaplaceMover, InterfaceNodesFollowTheMotionFixedNodesStaySlidingNodesStayOnTheirPlanes) {
  auto motion = motion_test::panel_motion(TimeFunction::constant(0.03));
  LaplaceMover mover(fluid(), motion_test::panel_groups(), motion);
  const auto [x, w] = at(mover, 0.0);
  const auto& X = fluid().nodes;
  for (Index n : fluid().group("panel").nodes) {
    const auto p = static_cast<std::size_t>(n);
    EXPECT_EQ(x[p].y(), X[p].y() + motion.deflection(X[p], 0.0));
    EXPECT_EQ(x[p].x(), X[p].x());
    EXPECT_EQ(x[p].z(), X[p].z());
  }
  const auto b = classify_fluid_boundary(fluid(), motion_test::panel_groups());
  for (Index n : b.fixed_nodes) EXPECT_EQ(x[static_cast<std::size_t>(n)], X[static_cast<std::size_t>(n)]);
  ASSERT_FALSE(b.sliding_nodes.empty());
  double moved = 0.0;
  for (Index n : b.sliding_nodes) {
    const auto p = static_cast<std::size_t>(n);
    ASSERT_EQ(x[p].z(), X[p].z());  // exactly on its symmetry plane
    moved = std::max(moved, (x[p] - X[p]).norm());
  }
  EXPECT_GT(moved, 0.01);  // the slab's nodes are not frozen by the symmetry planes
  // In the one-layer slab every node is on a symmetry plane: no free z component.
  EXPECT_TRUE(mover.free_nodes(2).empty());
  EXPECT_FALSE(mover.free_nodes(0).empty());
  EXPECT_GT(mover.memory_bytes(), 0u);
}

TEST(LaplaceMover, MeshVelocityIsTheTimeDerivativeOfThePositions) {
  auto motion = motion_test::panel_motion(TimeFunction::sine(0.02, 30.0));
  // A tight tolerance so that the solver error does not swamp the finite difference.
  LaplaceMover mover(fluid(), motion_test::panel_groups(), motion, 1e-14);
  const double t = 0.004, h = 2e-6;
  const auto [x, w] = at(mover, t);
  const auto [xp, wp] = at(mover, t + h);
  const auto [xm, wm] = at(mover, t - h);
  double max_w = 0, max_error = 0;
  for (std::size_t p = 0; p < x.size(); ++p) {
    max_w = std::max(max_w, w[p].norm());
    max_error = std::max(max_error, ((xp[p] - xm[p]) / (2 * h) - w[p]).norm());
  }
  EXPECT_GT(max_w, 1.0);  // 2 pi 30 Hz x 0.02 m = 3.8 m/s at the panel
  EXPECT_LT(max_error, 1e-6 * max_w);
}

TEST(LaplaceMover, DisplacementIsDiscretelyHarmonicToTheSolverTolerance) {
  // The panel deflects obliquely, so that both in-plane components have data.
  PanelModesMotion motion(Vec3(0.25, 0, 0), Vec3::UnitX(), 0.5, Vec3(0.6, 0.8, 0.0),
                          {{1, TimeFunction::constant(0.03)}});
  const double tolerance = 1e-10;
  LaplaceMover mover(fluid(), motion_test::panel_groups(), motion, tolerance);
  const auto [x, w] = at(mover, 0.0);
  const auto k = stiffness(fluid());
  const auto& X = fluid().nodes;
  const auto n = static_cast<Eigen::Index>(X.size());
  for (int c = 0; c < 2; ++c) {
    const auto free = mover.free_nodes(c);
    ASSERT_FALSE(free.empty());
    std::vector<bool> is_free(X.size(), false);
    for (Index i : free) is_free[static_cast<std::size_t>(i)] = true;
    Eigen::VectorXd u(n), prescribed(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      u[i] = x[static_cast<std::size_t>(i)][c] - X[static_cast<std::size_t>(i)][c];
      prescribed[i] = is_free[static_cast<std::size_t>(i)] ? 0.0 : u[i];
    }
    const Eigen::VectorXd r = k * u, b = k * prescribed;
    double r_free = 0.0, b_free = 0.0;
    for (Index i : free) {
      r_free += r[i] * r[i];
      b_free += b[i] * b[i];
    }
    r_free = std::sqrt(r_free);
    b_free = std::sqrt(b_free);
    EXPECT_GT(b_free, 0.0) << "component " << c;
    // CG stops on its recursively updated residual; the true one differs by round-off.
    EXPECT_LT(r_free, 1.01 * tolerance * b_free) << "component " << c;
  }
  EXPECT_LE(mover.last_error(), tolerance);
  EXPECT_GT(mover.last_iterations(), 0);
}

TEST(LaplaceMover, NoElementInvertsAtThreeCentimetres) {
  for (double a : {-0.03, 0.03}) {
    auto motion = motion_test::panel_motion(TimeFunction::constant(a));
    LaplaceMover mover(fluid(), motion_test::panel_groups(), motion);
    const auto [x, w] = at(mover, 0.0);
    EXPECT_EQ(mesh::summarize_quality(fluid(), x).inverted, 0) << "A = " << a;
  }
}

TEST(LaplaceMover, WarmStartNeedsFewerIterations) {
  auto motion = motion_test::panel_motion(TimeFunction::sine(0.02, 30.0));
  LaplaceMover mover(fluid(), motion_test::panel_groups(), motion);
  (void)at(mover, 0.004);
  const int cold = mover.last_iterations();
  (void)at(mover, 0.004 + 1e-5);
  EXPECT_LT(mover.last_iterations(), cold);
}

TEST(LaplaceMover, ASlidingPlaneNotNormalToAnAxisIsRejected) {
  // One tetrahedron: the face (0, 1, 2) on z = 0 moves, the face (1, 2, 3) is a tilted
  // sliding plane (node 3 slides on it).
  mesh::Mesh m;
  m.name = "fluid";
  m.source = "tilted.msh";
  m.nodes = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  m.node_tags = {1, 2, 3, 4};
  m.cells.type = mesh::ElementType::tet4;
  m.cells.connectivity = {0, 1, 2, 3};
  auto facet_group = [](std::string name, std::vector<Index> facet) {
    mesh::PhysicalGroup g;
    g.name = std::move(name);
    g.dim = 2;
    g.elements.type = mesh::ElementType::tri3;
    g.elements.connectivity = facet;
    std::sort(facet.begin(), facet.end());
    g.nodes = facet;
    return g;
  };
  m.groups = {facet_group("moving", {0, 2, 1}), facet_group("tilted", {1, 2, 3})};
  auto motion = motion_test::panel_motion(TimeFunction::constant(0.01));
  const BoundaryGroups groups{{"moving"}, {}, {"tilted"}};
  EXPECT_THROW({ LaplaceMover mover(m, groups, motion); }, InputError);
}
