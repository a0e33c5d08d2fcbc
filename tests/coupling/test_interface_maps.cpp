// Interface maps: closest points, snapping, orientation, exact transfer of linear fields,
// exact points on a curved shell, and the gap check.
#include <gtest/gtest.h>

#include <cmath>

#include "../shell/structured_shell_mesh.h"
#include "coupling_test_util.h"
#include "shellflow/core/error.h"
#include "shellflow/coupling/interface_maps.h"
#include "shellflow/coupling/shell_motion.h"
#include "shellflow/shell/shell_queries.h"

namespace shellflow::coupling {
namespace {

TEST(InterfaceMaps, FluidWallNodesLieOnTheShellAfterSnapping) {
  mesh::Mesh fluid = coupling_test::coarse_fluid();
  const shell::ShellModel model = coupling_test::panel_model(coupling_test::strip());
  const shell::ShellLocator locator(model);
  const WallNodeMap map = map_wall_nodes(fluid, "panel", locator);
  ASSERT_EQ(map.nodes, fluid.group("panel").nodes);
  EXPECT_LT(map.gap.max_gap, 1e-9);  // the panel is flat: the meshes agree
  snap_wall_nodes(fluid, map, model);
  const WallNodeMap again = map_wall_nodes(fluid, "panel", locator);
  for (std::size_t i = 0; i < again.nodes.size(); ++i) EXPECT_LT(again.gaps[i], 1e-9) << "node " << again.nodes[i];
}

TEST(InterfaceMaps, LoadPointsFindFluidTrianglesWithTheFluidAboveTheShell) {
  const mesh::Mesh& fluid = coupling_test::coarse_fluid();
  const shell::ShellModel model = coupling_test::panel_model(coupling_test::strip());
  const LoadPointMap map = map_load_points(model, fluid, "panel");
  ASSERT_EQ(map.sign.size(), model.load_points().size());
  EXPECT_LT(map.gap.max_gap, 1e-12);
  for (double s : map.sign) EXPECT_EQ(s, 1.0);  // V = +y points into the fluid (y > 0)
  // The wet faces are oriented out of the fluid: -y on the panel.
  for (const WetFace& f : oriented_wet_faces(fluid, "panel")) {
    const Vec3& a = fluid.nodes[std::size_t(f.nodes[0])];
    const Vec3 n = (fluid.nodes[std::size_t(f.nodes[1])] - a).cross(fluid.nodes[std::size_t(f.nodes[2])] - a);
    EXPECT_LT(n.y(), 0.0);
  }
}

TEST(InterfaceMaps, TransferALinearFieldExactlyBothWays) {
  mesh::Mesh fluid = coupling_test::coarse_fluid();
  const shell::ShellModel model = coupling_test::panel_model(coupling_test::strip());
  const auto f = [](const Vec3& x) { return 1.0 + 2.0 * x.x() - 3.0 * x.z() + 0.5 * x.y(); };
  // Fluid -> shell load points.
  const LoadPointMap map = map_load_points(model, fluid, "panel");
  std::vector<double> values(map.fluid_nodes.size()), out(map.sign.size());
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = f(fluid.nodes[std::size_t(map.fluid_nodes[i])]);
  transfer_to_load_points(map, values, out);
  for (std::size_t k = 0; k < out.size(); ++k) EXPECT_NEAR(out[k], f(model.load_points()[k].position), 1e-13);
  // Shell -> fluid wall nodes: a nodal displacement linear in X is reproduced at the nodes.
  const Vec3 a(1e-3, -2e-3, 0.5e-3);
  Mat3 B;
  B << 0.1, 0.2, -0.3, 0.05, -0.1, 0.2, 0.3, 0.0, 0.1;
  Eigen::VectorXd u = Eigen::VectorXd::Zero(model.num_dofs());
  for (Index j = 0; j < model.num_nodes(); ++j)
    u.segment<3>(shell::dofs_per_node * j) = a + B * model.mesh().nodes[std::size_t(j)];
  ShellStepMotion motion(model, 1e-6);
  const std::vector<Vec3> X = [&] {
    std::vector<Vec3> x;
    for (Index n : fluid.group("panel").nodes) x.push_back(fluid.nodes[std::size_t(n)]);
    return x;
  }();
  const int handle = motion.register_points(X);
  motion.set_state(0.0, u, u);
  std::vector<Vec3> d(X.size()), v(X.size());
  motion.evaluate(handle, 0.0, d, v);
  for (std::size_t i = 0; i < X.size(); ++i) EXPECT_LT((d[i] - (a + B * X[i])).norm(), 1e-14);
}

TEST(InterfaceMaps, ProjectionOnACurvedShellReproducesExactPoints) {
  // A cylindrical patch (radius 0.3 m, 60 degrees) of cubic triangles.
  const double R = 0.3;
  const mesh::Mesh m = shell::testing::structured_shell_mesh(
      R * M_PI / 3, 0.2, 6, 3, [&](double s, double t) { return Vec3(R * std::sin(s / R), R * std::cos(s / R), t); });
  const shell::ShellModel model = coupling_test::panel_model(m);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.num_dofs());
  // Points on the curved elements, x(xi), at interior parameters.
  std::vector<Vec3> points;
  for (Index e = 0; e < model.mesh().num_cells(); e += 3)
    for (const Vec2& xi : {Vec2(0.2, 0.3), Vec2(0.6, 0.1), Vec2(0.1, 0.05)})
      points.push_back(shell::mid_surface_position(model, {e, xi}, zero));
  // Displacement = the initial position: the interpolated displacement is the point itself.
  Eigen::VectorXd u = zero;
  for (Index j = 0; j < model.num_nodes(); ++j)
    u.segment<3>(shell::dofs_per_node * j) = model.mesh().nodes[std::size_t(j)];
  ShellStepMotion motion(model, 1e-6);
  const int handle = motion.register_points(points);
  motion.set_state(0.0, u, zero);
  std::vector<Vec3> d(points.size()), v(points.size());
  motion.evaluate(handle, 0.0, d, v);
  for (std::size_t i = 0; i < points.size(); ++i) EXPECT_LT((d[i] - points[i]).norm(), 1e-10) << "point " << i;
}

TEST(InterfaceMaps, AGapAboveMaxGapIsAnErrorNamingTheWorstNode) {
  mesh::Mesh lifted = coupling_test::strip();
  for (Vec3& x : lifted.nodes) x.y() += 2e-3;  // the shell 2 mm above the fluid wall
  const shell::ShellModel model = coupling_test::panel_model(lifted);
  const shell::ShellLocator locator(model);
  const WallNodeMap map = map_wall_nodes(coupling_test::coarse_fluid(), "panel", locator);
  EXPECT_NEAR(map.gap.max_gap, 2e-3, 1e-12);
  try {
    check_gap(map.gap, 1e-6, "fluid wall nodes -> shell");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("2.000e-03 m"), std::string::npos) << what;
    EXPECT_NE(what.find("fluid node"), std::string::npos) << what;
    EXPECT_NE(what.find("max_gap"), std::string::npos) << what;
  }
  EXPECT_NO_THROW(check_gap(map.gap, 3e-3, "fluid wall nodes -> shell"));
  EXPECT_THROW(map_wall_nodes(coupling_test::coarse_fluid(), "no_such_group", locator), InputError);
}

}  // namespace
}  // namespace shellflow::coupling
