// The load path of the coupling, end to end on the panel meshes: sign, uniform pressure
// against the shell-only follower pressure, and the force balance of the exchange.
#include <gtest/gtest.h>

#include "coupling_test_util.h"
#include "shellflow/coupling/flow.h"
#include "shellflow/coupling/partitioned_solver.h"
#include "shellflow/motion/mesh_mover.h"
#include "shellflow/shell/newmark_solver.h"

namespace shellflow::coupling {
namespace {

constexpr double p_ref = 28000.0, p_gas = 29000.0, dt = 1e-4;

void support(shell::ShellModel& m) {
  m.add_support(shell::Support::clamped("leading_edge"));
  m.add_support(shell::DirectionalSupport::roller("trailing_edge", Vec3::UnitX(), true));
  m.add_support(shell::DirectionalSupport::symmetry_plane("sides", Vec3::UnitZ()));
}

/// A closed slab of gas at rest at p_gas over the panel (every outer boundary a slip wall),
/// coupled to the clamped-sliding strip with the cavity at p_ref.
struct GasAtRest {
  mesh::Mesh fluid = coupling_test::coarse_fluid();
  shell::ShellModel model = coupling_test::panel_model(coupling_test::strip());
  std::unique_ptr<ShellStepMotion> motion;
  std::unique_ptr<FlowModel> flow;
  std::unique_ptr<shell::NewmarkSolver> solver;
  std::unique_ptr<PartitionedSolver> driver;

  GasAtRest() {
    support(model);
    model.add_follower_pressure({"", 1.0, TimeFunction::constant(0.0)});  // cavity at p_ref
    motion = std::make_unique<ShellStepMotion>(model, 1e-6);
    const shell::ShellLocator locator(model);
    WallNodeMap wall = map_wall_nodes(fluid, "panel", locator);
    snap_wall_nodes(fluid, wall, model);
    LoadPointMap loads = map_load_points(model, fluid, "panel");
    motion::SpaceMeshOptions so;
    so.interface_groups = {"panel"};
    so.fixed_groups = {"inflow", "outflow", "far_field", "wall"};
    so.sliding_groups = {"symmetry"};
    auto mover =
        std::make_unique<motion::SpaceMeshMover>(fluid, coupling_test::space(), so, *motion, model.mesh().nodes,
                                                 motion::lumped_node_areas(model.mesh().nodes, model.mesh().cells));
    std::vector<fluid::BoundaryCondition> bcs;
    for (const char* g : {"inflow", "outflow", "far_field", "wall", "panel"})
      bcs.emplace_back(g, fluid::BoundaryKind::slip_wall);
    bcs.emplace_back("symmetry", fluid::BoundaryKind::symmetry);
    fluid::FluidOptions fo;
    auto gas = std::make_unique<fluid::FluidModel>(fluid, fo, bcs);
    gas->set_state([](const Vec3&) { return fluid::Primitive{0.339, Vec3::Zero(), p_gas}; });
    FlowModelOptions options;
    options.substeps = 10;
    options.reference_pressure = p_ref;
    flow = std::make_unique<FlowModel>(fluid, std::move(gas), std::move(mover), *motion, std::move(wall),
                                       std::move(loads), options);
    solver = std::make_unique<shell::NewmarkSolver>(model);
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.num_dofs());
    solver->set_initial_state(zero, zero);
    PartitionedOptions po;
    po.predictor = LoadPredictor::none;
    driver = std::make_unique<PartitionedSolver>(model, *solver, *flow, *motion, po);
  }
};

TEST(CoupledLoads, AUniformGasPressureActsExactlyLikeTheShellOnlyFollowerPressure) {
  GasAtRest s;
  // Force balance of the exchange at t = 0: the resultant the shell receives equals the
  // force of the gas on the wet faces (uniform pressure: to round-off).
  const Vec3 shell_force = s.driver->shell_side_force(s.driver->pressure_rise());
  const Vec3 fluid_force = *s.flow->fluid_side_force();
  EXPECT_LT((shell_force - fluid_force).norm(), 1e-12 * fluid_force.norm());
  // 1000 Pa over 0.5 x 0.025 m, pushing the panel down into the cavity (-y).
  EXPECT_NEAR(shell_force.y(), -1000.0 * 0.5 * 0.025, 1e-9);

  s.driver->step(dt);

  shell::ShellModel reference = coupling_test::panel_model(coupling_test::strip());
  support(reference);
  reference.add_follower_pressure({"", -(p_gas - p_ref), TimeFunction::constant(1.0)});
  shell::NewmarkSolver alone(reference);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(reference.num_dofs());
  alone.set_initial_state(zero, zero);
  alone.advance(dt);
  const double scale = alone.displacement().cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0.0);
  EXPECT_LT((s.solver->displacement() - alone.displacement()).cwiseAbs().maxCoeff(), 1e-10 * scale);
  // A gas pressure above the cavity's pushes the panel into the cavity.
  const shell::ShellLocator locator(s.model);
  const auto mid = locator.closest(Vec3(0.5, 0.0, 0.0125)).point;
  EXPECT_LT(shell::interpolate_nodal(s.model, mid, s.solver->displacement()).y(), 0.0);
}

TEST(CoupledLoads, TheFluidWallFollowsTheShellAtTheEndOfEveryStep) {
  GasAtRest s;
  for (int i = 0; i < 3; ++i) s.driver->step(dt);
  const auto x = s.flow->positions();
  const auto& wall = s.flow->wall_map();
  for (std::size_t i = 0; i < wall.nodes.size(); ++i) {
    const Vec3 shell_x = shell::mid_surface_position(s.model, wall.points[i], s.solver->displacement());
    EXPECT_LT((x[std::size_t(wall.nodes[i])] - shell_x).norm(), 1e-15) << "wall node " << wall.nodes[i];
  }
  EXPECT_DOUBLE_EQ(s.flow->time(), s.solver->time());
}

TEST(CoupledLoads, GasAtRestStaysExactlyAtRestWhileTheShellMovesTheMeshTangentially) {
  // The shell slides along x (no normal wall velocity): the space mesh moves every fluid
  // node, and with w = dx/dt the uniform state is kept to round-off (discrete GCL).
  GasAtRest s;
  const Index nd = s.model.num_dofs();
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(nd);
  Eigen::VectorXd u1 = zero;
  for (Index j = 0; j < s.model.num_nodes(); ++j) u1[shell::dofs_per_node * j] = 2e-4;
  const fluid::FluidState U0 = s.flow->flow()->state();
  s.motion->set_window(0.0, dt, zero, zero, u1, zero);
  s.flow->advance(*s.motion, dt);
  double speed = 0.0;
  for (std::size_t a = 0; a < s.fluid.nodes.size(); ++a)
    speed = std::max(speed, s.flow->flow()->mesh_velocity()[a].norm());
  EXPECT_GT(speed, 0.1);  // the mesh moves (the wall by 2e-4 m in 1e-4 s, from rest to rest)
  for (const Index a : s.flow->wall_map().nodes)
    EXPECT_LT((s.flow->positions()[std::size_t(a)] - s.fluid.nodes[std::size_t(a)] - Vec3(2e-4, 0, 0)).norm(), 1e-15);
  s.motion->set_window(dt, dt, u1, zero, zero, zero);
  s.flow->advance(*s.motion, 2 * dt);
  const fluid::FluidState& U = s.flow->flow()->state();
  double change = 0.0;
  for (int v = 0; v < fluid::num_variables; ++v)
    for (std::size_t a = 0; a < U.var[std::size_t(v)].size(); ++a)
      change =
          std::max(change, std::abs(U.var[std::size_t(v)][a] - U0.var[std::size_t(v)][a]) / (v == 4   ? U0.var[4][a]
                                                                                             : v == 0 ? 0.339
                                                                                                      : 0.339 * 300.0));
  EXPECT_LT(change, 1e-12);
}

}  // namespace
}  // namespace shellflow::coupling
