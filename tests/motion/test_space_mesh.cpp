#include <gtest/gtest.h>

#include <random>

#include "motion_test_util.h"
#include "shellflow/core/error.h"
#include "shellflow/fem/shape_functions.h"
#include "shellflow/motion/space_mesh.h"

using namespace shellflow;
using namespace shellflow::motion;
using motion_test::fluid;
using motion_test::space;

namespace {

/// One curved 20-node tetrahedron: the reference element's nodes mapped by an affine map
/// plus a smooth cubic perturbation (so its faces and edges are curved).
mesh::Mesh curved_tet() {
  mesh::Mesh m;
  m.name = "curved";
  m.source = "test";
  m.cells.type = mesh::ElementType::tet20;
  Mat3 A;
  A << 1.0, 0.2, 0.1, -0.1, 0.9, 0.3, 0.2, -0.2, 1.1;
  for (const auto& xi : fem::Tet20::nodes()) {
    const Vec3 r(xi[0], xi[1], xi[2]);
    const Vec3 bump(0.05 * r.y() * r.z() * (1 + r.x()), -0.04 * r.x() * r.x() * r.z(), 0.06 * r.x() * r.y() * r.y());
    m.nodes.push_back(A * r + bump);
    m.node_tags.push_back(m.nodes.size());
  }
  for (Index a = 0; a < 20; ++a) m.cells.connectivity.push_back(a);
  return m;
}

Vec3 map(const mesh::Mesh& m, const Vec3& xi) {
  double N[20];
  fem::Tet20::eval(xi.data(), N);
  Vec3 x = Vec3::Zero();
  for (int a = 0; a < 20; ++a) x += N[a] * m.nodes[static_cast<std::size_t>(a)];
  return x;
}

}  // namespace

TEST(SpaceMeshLocation, RandomPointsInACurvedElementAreFoundToRoundOff) {
  const mesh::Mesh m = curved_tet();
  SpaceMesh space_mesh(m, SpaceMeshOptions{});
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> xi_true, points;
  while (points.size() < 500) {
    const Vec3 xi(u(rng), u(rng), u(rng));
    if (xi.sum() > 1.0) continue;
    xi_true.push_back(xi);
    points.push_back(map(m, xi));
  }
  const auto report = space_mesh.locate(points);
  EXPECT_EQ(report.located, 500);
  EXPECT_EQ(report.projected, 0);
  const double h = 1.5;
  EXPECT_LT(report.max_residual, 1e-10 * h);
  // Interpolating the node positions with the stored shape values gives the point back.
  std::vector<Vec3> x(points.size()), w(points.size());
  space_mesh.interpolate(x, w);
  for (std::size_t p = 0; p < points.size(); ++p) EXPECT_LT((x[p] - points[p]).norm(), 1e-10 * h);
}

TEST(SpaceMeshLocation, APointOutsideIsReportedWithTheNode) {
  SpaceMesh space_mesh(curved_tet(), SpaceMeshOptions{});
  const std::vector<Vec3> points{Vec3(0.1, 0.1, 0.1), Vec3(5.0, 5.0, 5.0)};
  try {
    space_mesh.locate(points);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("fluid node 1"), std::string::npos) << e.what();
  }
}

TEST(SpaceMeshLocation, EveryNodeOfThePanelFluidMeshIsLocated) {
  SpaceMesh space_mesh(space(), motion_test::panel_options());
  const auto report = space_mesh.locate(fluid().nodes);
  EXPECT_EQ(report.located + report.projected, fluid().num_nodes());
  EXPECT_LT(report.max_gap, 1e-9);
  EXPECT_LT(report.max_residual, 1e-12);
  std::vector<Vec3> x(fluid().nodes.size()), w(x.size());
  space_mesh.interpolate(x, w);
  double worst = 0;
  for (std::size_t p = 0; p < x.size(); ++p) worst = std::max(worst, (x[p] - fluid().nodes[p]).norm());
  EXPECT_EQ(worst, 0.0);  // unmoved: x = X + sum N * 0
}

TEST(SpaceMeshClasses, PanelNodesAreClassifiedWithPrecedence) {
  const SpaceMesh space_mesh(space(), motion_test::panel_options());
  const auto classes = space_mesh.node_classes();
  const auto& nodes = space().nodes;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const Vec3& x = nodes[i];
    const bool on_panel = std::abs(x.y()) < 1e-12 && x.x() > 0.25 - 1e-12 && x.x() < 0.75 + 1e-12;
    const bool on_outer = std::abs(x.y()) < 1e-12 || std::abs(x.y() - 0.4) < 1e-12 || std::abs(x.x()) < 1e-12 ||
                          std::abs(x.x() - 1.0) < 1e-12;
    const bool on_symmetry = std::abs(x.z()) < 1e-12 || std::abs(x.z() - 0.025) < 1e-12;
    const NodeClass expected = on_panel      ? NodeClass::interface
                               : on_outer    ? NodeClass::fixed
                               : on_symmetry ? NodeClass::sliding
                                             : NodeClass::interior;
    EXPECT_EQ(classes[i], expected) << "node " << i << " at " << x.transpose();
  }
  // High-order nodes inside the slab (z = h/3, 2h/3) are interior.
  EXPECT_GT(std::count(classes.begin(), classes.end(), NodeClass::interior), 0);
}

TEST(SpaceMeshInterpolation, ReproducesACubicDisplacementFieldExactly) {
  SpaceMesh space_mesh(space(), motion_test::panel_options());
  space_mesh.locate(fluid().nodes);
  auto field = [](const Vec3& X) {
    return Vec3(0.01 * X.x() * X.y() * X.y() - 0.02 * X.z() * X.x(), 0.03 * X.x() * X.x() * X.x(),
                0.004 * X.y() * X.z() * X.x());
  };
  std::vector<Vec3> u, v;
  for (const Vec3& X : space().nodes) {
    u.push_back(field(X));
    v.push_back(2.0 * field(X));
  }
  space_mesh.set_node_motion(u, v);
  std::vector<Vec3> x(fluid().nodes.size()), w(x.size());
  space_mesh.interpolate(x, w);
  for (std::size_t p = 0; p < x.size(); ++p) {
    const Vec3& X = fluid().nodes[p];
    ASSERT_LT((x[p] - X - field(X)).norm(), 1e-14) << "fluid node " << p;
    ASSERT_LT((w[p] - 2.0 * field(X)).norm(), 1e-14) << "fluid node " << p;
  }
}

TEST(SpaceMeshIdw, UniformTranslationMovesEveryNodeByExactlyThatTranslation) {
  for (auto weighting : {IdwWeighting::plain, IdwWeighting::area}) {
    SpaceMesh space_mesh(space(), motion_test::panel_options(3.0, weighting));
    // Samples: the shell nodes with their lumped areas.
    const auto& shell = motion_test::shell();
    space_mesh.set_interface_samples(shell.nodes, lumped_node_areas(shell.nodes, shell.cells));
    space_mesh.locate(fluid().nodes);
    const Vec3 d(0.013, -0.021, 0.0);  // parallel to the symmetry planes z = const
    const Vec3 dv(0.5, 0.25, 0.0);
    const std::vector<Vec3> iu(space_mesh.interface_nodes().size(), d), iv(space_mesh.interface_nodes().size(), dv),
        su(shell.nodes.size(), d), sv(shell.nodes.size(), dv), fu(space_mesh.fixed_nodes().size(), d);
    space_mesh.move(iu, iv, su, sv, fu);
    for (const Vec3& u : space_mesh.displacement()) ASSERT_LT((u - d).norm(), 1e-15);
    std::vector<Vec3> x(fluid().nodes.size()), w(x.size());
    space_mesh.interpolate(x, w);
    for (std::size_t p = 0; p < x.size(); ++p) {
      ASSERT_LT((x[p] - fluid().nodes[p] - d).norm(), 1e-14);
    }
    // Velocities of interior nodes: the IDW of the sample velocities alone (fixed nodes have
    // no velocity), so a uniform sample velocity gives a fraction of it, never more.
    for (const Vec3& v : space_mesh.velocity()) ASSERT_LE(v.norm(), dv.norm() * (1 + 1e-14));
  }
}

TEST(SpaceMeshIdw, SlidingNodesStayOnTheirPlanes) {
  SpaceMesh space_mesh(space(), motion_test::panel_options());
  const auto& shell = motion_test::shell();
  space_mesh.set_interface_samples(shell.nodes, {});
  space_mesh.locate(fluid().nodes);
  // A sample motion with a z component: sliding nodes must not leave z = 0 / z = 0.025.
  const Vec3 d(0.0, 0.05, 0.02);
  const std::vector<Vec3> iu(space_mesh.interface_nodes().size(), Vec3(0, 0.05, 0)), iv(iu.size(), Vec3::Zero()),
      su(shell.nodes.size(), d), sv(shell.nodes.size(), d);
  space_mesh.move(iu, iv, su, sv);
  const auto x = space_mesh.current_positions();
  Index sliding = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (space_mesh.node_classes()[i] != NodeClass::sliding) continue;
    ++sliding;
    const double z0 = space().nodes[i].z();
    EXPECT_EQ(x[i].z(), z0) << "node " << i;
    EXPECT_EQ(space_mesh.velocity()[i].z(), 0.0);
  }
  EXPECT_GT(sliding, 0);
  // Fluid nodes on the symmetry planes stay there to round-off.
  std::vector<Vec3> xf(fluid().nodes.size()), wf(xf.size());
  space_mesh.interpolate(xf, wf);
  for (Index n : fluid().group("symmetry").nodes) {
    EXPECT_NEAR(xf[static_cast<std::size_t>(n)].z(), fluid().nodes[static_cast<std::size_t>(n)].z(), 1e-15);
  }
}

TEST(SpaceMeshJacobian, UndeformedStraightMeshHasUnitRelativeJacobian) {
  const SpaceMesh space_mesh(space(), motion_test::panel_options());
  // Straight elements: det J is constant and equals the vertex determinant up to the
  // round-off of Gmsh's high-order node positions, amplified by the slivers' conditioning.
  EXPECT_NEAR(space_mesh.min_relative_jacobian(), 1.0, 1e-10);
}

TEST(SpaceMeshErrors, NotCubicOrMissingGroupAreInputErrors) {
  EXPECT_THROW(SpaceMesh(fluid(), motion_test::panel_options()), InputError);
  auto options = motion_test::panel_options();
  options.fixed_groups.push_back("no_such_group");
  EXPECT_THROW(SpaceMesh(space(), options), InputError);
}
