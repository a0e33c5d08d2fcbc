// Whole coupled runs from the case files (slow): the rigid panel in the Mach 2.3 stream, and
// the paper's mesh-motion test driven by the shell.
#include <gtest/gtest.h>

#include "coupling_test_util.h"
#include "shellflow/io/case_meshes.h"
#include "shellflow/mesh/quality.h"
#include "shellflow/setup/coupled_setup.h"
#include "shellflow/setup/shell_setup.h"

namespace shellflow::coupling {
namespace {

TEST(CoupledRuns, ARigidFlatPanelInTheFreeStreamStaysAtRestAndTheFlowUnchanged) {
  // The coarse Euler flutter case without the cavity perturbation: the flat panel in the
  // M 2.3 stream feels exactly p_inf on both faces.
  io::Case c = io::read_case(coupling_test::cases_dir / "panel_flutter" / "clamped_clamped_coarse.yaml");
  c.coupling->cavity_pressure.reset();
  const io::CaseMeshes meshes = io::load_case_meshes(c, std::nullopt);
  setup::CoupledSystem s = setup::build_coupled_system(c, meshes);
  const fluid::FluidState U0 = s.flow->flow()->state();
  long fluid_steps = 0;
  while (fluid_steps < 10000) fluid_steps += s.driver->step(c.time->step).flow.substeps;
  // The flow changes at round-off level only (below), so the panel feels round-off loads
  // (~1e-10 Pa) and moves by round-off (~1e-15 m, against a flutter amplitude of 1e-4 m).
  EXPECT_LT(s.solver->displacement().cwiseAbs().maxCoeff(), 1e-12);
  const fluid::FluidState& U = s.flow->flow()->state();
  double change = 0.0;
  for (int v = 0; v < fluid::num_variables; ++v)
    for (std::size_t a = 0; a < U.var[std::size_t(v)].size(); ++a) {
      const double scale = v == 0 ? 0.339 : v == 4 ? U0.var[4][a] : 0.339 * 782.0;
      change = std::max(change, std::abs(U.var[std::size_t(v)][a] - U0.var[std::size_t(v)][a]) / scale);
    }
  std::printf("%ld fluid steps: largest relative change of the flow %.3e\n", fluid_steps, change);
  EXPECT_LT(change, 1e-10);
}

TEST(CoupledRuns, MeshMotionTestFollowsTheShellWithoutInvertingAndAsTheShellAlone) {
  for (const char* file : {"up_5000.yaml", "antisymmetric_15000.yaml"}) {
    const io::Case c = io::read_case(coupling_test::cases_dir / "mesh_motion_tests" / file);
    const io::CaseMeshes meshes = io::load_case_meshes(c, std::nullopt);
    setup::CoupledSystem s = setup::build_coupled_system(c, meshes);
    shell::ShellModel reference = setup::build_shell_model(*c.shell, *meshes.shell);
    shell::NewmarkSolver alone(reference, setup::newmark_options(*c.shell->analysis),
                               [f = c.shell->analysis->load_function](double t) { return f.value(t); });
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(reference.num_dofs());
    alone.set_initial_state(zero, zero);
    double min_quality = 1.0;
    const auto steps = static_cast<long>(std::llround(c.time->end / c.time->step));
    for (long i = 0; i < steps; ++i) {
      s.driver->step(c.time->step);  // throws SolverError on an inverted element
      alone.advance(c.time->step);
      for (double q : mesh::cell_qualities(*s.fluid_mesh, s.flow->positions())) min_quality = std::min(min_quality, q);
      const double scale = alone.displacement().cwiseAbs().maxCoeff();
      EXPECT_LE((s.solver->displacement() - alone.displacement()).cwiseAbs().maxCoeff(), 1e-10 * scale) << file;
    }
    double w = 0.0;
    for (Index j = 0; j < s.shell->num_nodes(); ++j)
      w = std::max(w, std::abs(s.solver->displacement()[shell::dofs_per_node * j + 1]));
    std::printf("%s: largest panel deflection at the end %.4f m, lowest fluid mean-ratio quality %.3f\n", file, w,
                min_quality);
    EXPECT_GT(min_quality, 0.0) << file;
  }
}

}  // namespace
}  // namespace shellflow::coupling
