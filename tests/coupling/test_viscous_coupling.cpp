// The viscous traction of the gas on the shell (paper eqs. 29-30, docs/coupling.md "Viscous
// traction"): a no-slip wet wall moves with the shell and passes the wall shear.
//   - the shear-loaded strip under plane Couette flow (cases/viscous_coupling/couette_strip.yaml):
//     the strip's end displacement against tau L^2 / (2 E' h), the shear force balance;
//   - Stokes' first problem in a channel: gas at rest over the strip set sliding at U,
//     against the exact series solution;
//   - a slip wet wall of a viscous flow passes no shear.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include "coupling_test_util.h"
#include "shellflow/io/case_meshes.h"
#include "shellflow/setup/coupled_setup.h"

namespace shellflow::coupling {
namespace {

const auto couette_file = coupling_test::cases_dir / "viscous_coupling" / "couette_strip.yaml";

std::string read_text(const std::filesystem::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

/// `text` with its one occurrence of `from` replaced by `to`.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  EXPECT_EQ(text.find(from, at + 1), std::string::npos) << from;
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

// The case's numbers (couette_strip.yaml).
constexpr double L = 0.1, H = 0.01, W = 0.004;
constexpr double mu = 0.2, rho = 1.16, lid_speed = 5.0;
constexpr double young = 2.5e7, poisson = 0.3, thickness = 4e-3;

TEST(ViscousCoupling, ShearLoadedStripEndDisplacementMatchesTheExactCouetteShear) {
  const io::Case c = io::read_case(couette_file);
  const io::CaseMeshes meshes = io::load_case_meshes(c, std::nullopt);
  setup::CoupledSystem s = setup::build_coupled_system(c, meshes);
  ASSERT_TRUE(s.aerodynamics->has_shear());
  CouplingStepReport r;
  const auto steps = std::lround(c.time->end / c.time->step);
  for (long i = 0; i < steps; ++i) r = s.driver->step(c.time->step);
  // The end of the strip (x = L) along x.
  double end = 0.0;
  for (Index j = 0; j < s.shell->num_nodes(); ++j)
    if (std::abs(s.shell->mesh().nodes[std::size_t(j)].x() - L) < 1e-12)
      end = std::max(end, s.solver->displacement()[shell::dofs_per_node * j]);
  const double tau = mu * lid_speed / H;
  const double exact = tau * L * L / (2 * young / (1 - poisson * poisson) * thickness);
  const Vec3 fluid = *r.fluid_force;
  std::printf(
      "Couette strip: end displacement %.6e m (exact %.6e, %+.3f %%); shear force fluid %.9f N, shell %.9f N "
      "(tau L W = %.6f N), balance in x %.2e\n",
      end, exact, 100 * (end / exact - 1), fluid.x(), r.shell_force.x(), tau * L * W,
      std::abs(fluid.x() - r.shell_force.x()) / fluid.x());
  EXPECT_NEAR(end / exact, 1.0, 0.01);
  EXPECT_NEAR(fluid.x() / (tau * L * W), 1.0, 2e-3);
  // The shear passes whole: the shell gets what the fluid gives, in x, to round-off.
  EXPECT_LT(std::abs(fluid.x() - r.shell_force.x()), 1e-8 * fluid.x());
  EXPECT_LT(std::abs(fluid.z() - r.shell_force.z()), 1e-8 * fluid.x());
}

TEST(ViscousCoupling, GasAtRestIsDraggedByTheSlidingStripAsStokesFirstProblemPredicts) {
  // The channel of the Couette strip with the lid at rest, gas at rest, and the strip set
  // sliding along x at U from t = 0 (its motion given: the shell's Hermite window). Exact:
  // u/U = 1 - y/H - sum_n 2/(n pi) sin(n pi y/H) exp(-n^2 pi^2 nu t/H^2); the channel's ends
  // hold it (40 terms).
  constexpr double U = 1.0, nu = mu / rho, pi = std::numbers::pi;
  std::string series = fmt::format("{}*(1 - y/{}", U, H);
  for (int n = 1; n <= 40; ++n)
    series += fmt::format(" - {:.17g}*sin({:.17g}*y)*exp(-{:.17g}*t)", 2 / (n * pi), n * pi / H,
                          n * n * pi * pi * nu / (H * H));
  series += ")";
  std::string text = read_text(couette_file);
  text = replaced(text, "velocity: [5, 0, 0], temperature: 300.3", "temperature: 300.3");
  text = replaced(text, R"(    - { group: inlet, type: no_slip_wall, velocity: ["5*y/0.01", 0, 0] })",
                  fmt::format(R"(    - {{ group: inlet, type: no_slip_wall, velocity: ["{}", 0, 0] }})", series));
  text = replaced(text, R"(    - { group: outlet, type: no_slip_wall, velocity: ["5*y/0.01", 0, 0] })",
                  fmt::format(R"(    - {{ group: outlet, type: no_slip_wall, velocity: ["{}", 0, 0] }})", series));
  text = replaced(text, R"(    initial: { density: 1.16, velocity: ["5*y/0.01", 0, 0], pressure: 1.0e5 })", "");
  const io::Case c = io::read_case_string(text, couette_file);
  const io::CaseMeshes meshes = io::load_case_meshes(c, std::nullopt);
  setup::CoupledSystem s = setup::build_coupled_system(c, meshes);
  const Index ndof = s.shell->num_dofs();
  Eigen::VectorXd u0 = Eigen::VectorXd::Zero(ndof), v = Eigen::VectorXd::Zero(ndof);
  for (Index j = 0; j < s.shell->num_nodes(); ++j) v[shell::dofs_per_node * j] = U;  // rigid slide along x
  const double dt = c.time->step;
  // The gas at mid-channel (x = L/2), by height.
  std::vector<Index> probe;
  for (Index a = 0; a < s.fluid_mesh->num_nodes(); ++a)
    if (std::abs(s.fluid_mesh->nodes[std::size_t(a)].x() - L / 2) < 1e-9) probe.push_back(a);
  ASSERT_GE(probe.size(), 22u);
  double t = 0.0;
  for (const double check : {4e-5, 1e-4, 2e-4}) {
    while (t < check - 1e-12) {
      const Eigen::VectorXd u1 = u0 + dt * v;
      s.motion->set_window(t, dt, u0, v, u1, v);
      s.flow->advance(*s.motion, t + dt);
      u0 = u1;
      t += dt;
    }
    double error = 0.0;
    for (const Index a : probe) {
      const double y = s.fluid_mesh->nodes[std::size_t(a)].y();
      double exact = 1 - y / H;
      for (int n = 1; n <= 200; ++n)
        exact -= 2 / (n * pi) * std::sin(n * pi * y / H) * std::exp(-n * n * pi * pi * nu * t / (H * H));
      error = std::max(error, std::abs(s.flow->flow()->primitive(a).velocity.x() / U - exact));
    }
    std::printf("Stokes' first problem: t = %.0e s (2 sqrt(nu t) = %.2f H): max |u - u_exact| / U = %.2e\n", t,
                2 * std::sqrt(nu * t) / H, error);
    EXPECT_LT(error, t < 5e-5 ? 5e-3 : 2e-3) << "t = " << t;  // measured 1.8e-3, 8.4e-4, 2.3e-4
  }
}

TEST(ViscousCoupling, ASlipWetWallOfAViscousFlowPassesNoShear) {
  std::string text = read_text(couette_file);
  text = replaced(text, "- { group: strip, type: no_slip_wall, temperature: 300.3 }",
                  "- { group: strip, type: slip_wall }");
  const io::Case c = io::read_case_string(text, couette_file);
  const io::CaseMeshes meshes = io::load_case_meshes(c, std::nullopt);
  setup::CoupledSystem s = setup::build_coupled_system(c, meshes);
  EXPECT_FALSE(s.aerodynamics->has_shear());
  EXPECT_EQ(s.driver->loads().size(), s.shell->load_points().size());  // pressure only
  const CouplingStepReport r = s.driver->step(c.time->step);
  EXPECT_EQ(r.shell_force.x(), 0.0);
}

}  // namespace
}  // namespace shellflow::coupling
