// setup/coupled_setup.h on its own: what build_coupled_system makes of the shipped cases (the
// aerodynamic model a case asks for, the renumbered and snapped fluid mesh, the initial
// state, the force balance of the exchange), and the case errors it reports with context.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "shellflow/core/error.h"
#include "shellflow/io/case.h"
#include "shellflow/io/case_meshes.h"
#include "shellflow/setup/coupled_setup.h"

namespace shellflow::setup {
namespace {

const std::filesystem::path cases = std::filesystem::path(SHELLFLOW_SOURCE_DIR) / "cases" / "panel_flutter";

io::Case read(const std::string& file, const std::vector<std::string>& sets = {}) {
  std::vector<io::KeyOverride> overrides;
  for (const auto& s : sets) overrides.push_back(io::KeyOverride::parse(s));
  return io::read_case(cases / file, overrides);
}

TEST(CoupledSetup, APistonTheoryCaseGetsPistonLoadsAndNoFluidMesh) {
  const io::Case c = read("clamped_clamped_piston.yaml");
  const io::CaseMeshes meshes = io::load_case_meshes(c, std::nullopt);
  const CoupledSystem s = build_coupled_system(c, meshes);
  ASSERT_TRUE(s.shell && s.solver && s.driver && s.aerodynamics);
  EXPECT_NE(s.piston, nullptr);
  EXPECT_EQ(s.flow, nullptr);
  EXPECT_EQ(s.fluid_mesh, nullptr);
  EXPECT_FALSE(s.aerodynamics->has_shear());
  EXPECT_DOUBLE_EQ(s.reference_pressure, c.fluid->free_stream.pressure);
  // At rest in a uniform stream piston theory gives no pressure rise.
  for (const double dp : s.driver->pressure_rise()) EXPECT_EQ(dp, 0.0);
}

TEST(CoupledSetup, AnEulerCaseGetsItsFlowOnARenumberedMeshWithTheWallOnTheShell) {
  const io::Case c = read("clamped_clamped_coarse.yaml", {"meshes.fluid.size_factor=3"});
  const io::CaseMeshes meshes = io::load_case_meshes(c, std::nullopt);
  const CoupledSystem s = build_coupled_system(c, meshes);
  ASSERT_NE(s.flow, nullptr);
  ASSERT_NE(s.fluid_mesh, nullptr);
  EXPECT_EQ(s.piston, nullptr);
  EXPECT_DOUBLE_EQ(s.reference_pressure, c.fluid->free_stream.pressure);
  // new_index is a permutation of the case mesh's nodes.
  const std::size_t n = meshes.fluid->nodes.size();
  ASSERT_EQ(s.new_index.size(), n);
  std::vector<Index> sorted = s.new_index;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t k = 0; k < n; ++k) ASSERT_EQ(sorted[k], Index(k));
  // Nodes away from the wet wall keep their positions under the renumbering; the snapped wall
  // moved by less than the geometry's tolerance.
  double moved = 0.0;
  for (std::size_t k = 0; k < n; ++k)
    moved = std::max(moved, (s.fluid_mesh->nodes[std::size_t(s.new_index[k])] - meshes.fluid->nodes[k]).norm());
  EXPECT_LT(moved, 1e-6);
  // The initial state: the free stream over a shell at rest, and the force balance of the
  // exchange holds (the gas at the free-stream pressure over a cavity at the same pressure).
  const auto fluid_force = s.flow->fluid_side_force();
  ASSERT_TRUE(fluid_force);
  const Vec3 shell_force = s.driver->shell_side_force(s.driver->pressure_rise());
  EXPECT_LT((shell_force - *fluid_force).norm(), 1e-9 * c.fluid->free_stream.pressure);
}

/// The pressure the coupled flow starts with at every node off the boundaries that impose a state (the inflow and
/// the far field; walls and symmetry planes change the velocity only), against `expected`.
void expect_initial_pressure(const std::vector<std::string>& sets, const std::function<double(const Vec3&)>& expected) {
  std::vector<std::string> all = {"meshes.fluid.size_factor=3"};
  all.insert(all.end(), sets.begin(), sets.end());
  const io::Case c = read("clamped_clamped_coarse.yaml", all);
  const io::CaseMeshes meshes = io::load_case_meshes(c, std::nullopt);
  const CoupledSystem s = build_coupled_system(c, meshes);
  ASSERT_NE(s.flow, nullptr);
  std::vector<bool> on_boundary(s.fluid_mesh->nodes.size(), false);
  for (const char* group : {"inflow", "far_field"})
    for (const Index a : s.fluid_mesh->group(group).nodes) on_boundary[std::size_t(a)] = true;
  int checked = 0;
  for (std::size_t a = 0; a < on_boundary.size(); ++a) {
    if (on_boundary[a]) continue;
    const Vec3& x = s.fluid_mesh->nodes[a];
    ASSERT_NEAR(s.flow->flow()->pressure(Index(a)), expected(x), 1e-9 * expected(x)) << "node at " << x.transpose();
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

TEST(CoupledSetup, ACoupledFlowStartsFromTheFreeStreamByDefault) {
  expect_initial_pressure({}, [](const Vec3&) { return 28000.0; });  // the case's free_stream.pressure
}

TEST(CoupledSetup, ACoupledFlowStartsFromTheCasesRiemannProblem) {
  expect_initial_pressure({"fluid.analysis.riemann={position: 0.5, left: {density: 0.8, pressure: 4e4}, "
                           "right: {density: 0.4, pressure: 2e4}}"},
                          [](const Vec3& x) { return x.x() < 0.5 ? 4e4 : 2e4; });
}

TEST(CoupledSetup, ACoupledFlowStartsFromTheCasesInitialField) {
  expect_initial_pressure({"fluid.analysis.initial={density: 0.4, velocity: [100, 0, 0], pressure: '2e4*(1 + x)'}"},
                          [](const Vec3& x) { return 2e4 * (1.0 + x.x()); });
}

TEST(CoupledSetup, AWetGroupOffTheShellIsRefusedWithTheGapAndTheFix) {
  // The inflow face as the wet group: its nodes lie up to 0.47 m from the panel.
  const io::Case c = read("clamped_clamped_coarse.yaml", {"meshes.fluid.size_factor=3", "coupling.fluid_group=inflow",
                                                          "motion.interface_groups=[inflow]",
                                                          "motion.fixed_groups=[panel, outflow, far_field, wall]"});
  const io::CaseMeshes meshes = io::load_case_meshes(c, std::nullopt);
  try {
    (void)build_coupled_system(c, meshes);
    FAIL() << "a wet group off the shell was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("clamped_clamped_coarse.yaml:"), std::string::npos) << what;  // the coupling section
    EXPECT_NE(what.find("the largest gap is 4.7"), std::string::npos) << what;
    EXPECT_NE(what.find("check the geometry and coupling.fluid_group, or raise max_gap"), std::string::npos) << what;
  }
}

TEST(CoupledSetup, TheAddedMassRatioIsRhoATimesTheStepOverTheShellsMassPerArea) {
  const io::Case c = read("clamped_clamped_piston.yaml");
  const double a = std::sqrt(c.fluid->gas.gamma * c.fluid->free_stream.pressure / c.fluid->free_stream.density);
  EXPECT_NEAR(added_mass_ratio(c),
              c.fluid->free_stream.density * a * c.time->step / (c.shell->material.density * c.shell->thickness),
              1e-14);
}

}  // namespace
}  // namespace shellflow::setup
