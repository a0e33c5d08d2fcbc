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
#include <map>
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

namespace shellflow::coupling {
namespace {

/// The laminar Mach 2 boundary layer of boundary_layer_panel.yaml, its flow converged with
/// local time steps over the panel held flat (the steady state of the coupled run, reached in
/// a few thousand iterations instead of some 10^5 global steps).
struct BoundaryLayer {
  double cf_mid = 0.0, cf_exact_mid = 0.0;
  double fluid_force = 0.0, shell_force = 0.0, exact_force = 0.0;
  int iterations = 0;
  double rate = 0.0;
};

BoundaryLayer boundary_layer(double size_factor, int iterations) {
  std::string text = read_text(coupling_test::cases_dir / "viscous_coupling" / "boundary_layer_panel.yaml");
  if (size_factor != 1.0)
    text = replaced(text, "fluid: { geo: boundary_layer_slab.geo, order: 1 }",
                    fmt::format("fluid: {{ geo: boundary_layer_slab.geo, order: 1, size_factor: {} }}", size_factor));
  const io::Case c =
      io::read_case_string(text, coupling_test::cases_dir / "viscous_coupling" / "boundary_layer_panel.yaml");
  const io::CaseMeshes meshes = io::load_case_meshes(c, std::nullopt);
  setup::CoupledSystem s = setup::build_coupled_system(c, meshes);
  fluid::FluidModel& flow = *s.flow->flow();
  BoundaryLayer r;
  for (; r.iterations < iterations; ++r.iterations) flow.step_local(0.5);
  r.rate = flow.density_rate();
  const double gamma = 1.4, rho = 0.010514, p = 870.0, mach = 2.0;
  const double speed = mach * std::sqrt(gamma * p / rho);
  const double temperature = p / (rho * 287.05);
  const double mu = 1.789e-5 * temperature / 288.15;
  const double q = 0.5 * rho * speed * speed, re1 = rho * speed / mu;
  // Skin friction at mid-panel (x = 0.5 m): linear between the wall nodes on either side
  // (each the mean over the nodes across the slab).
  const auto& nodes = s.fluid_mesh->group("panel").nodes;
  std::vector<Vec3> shear(nodes.size());
  flow.wall_shear("panel", shear);
  std::map<long, std::pair<double, int>> by_x;  // x in micrometres -> (sum of tau_x, count)
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    auto& [sum, count] = by_x[std::lround(flow.positions()[std::size_t(nodes[k])].x() * 1e6)];
    sum += shear[k].x();
    ++count;
  }
  const auto above = by_x.lower_bound(500000);
  const auto below = std::prev(above);
  const double x0 = below->first * 1e-6, x1 = above->first * 1e-6;
  const double t0 = below->second.first / below->second.second, t1 = above->second.first / above->second.second;
  r.cf_mid = (t0 + (t1 - t0) * (0.5 - x0) / (x1 - x0)) / q;
  r.cf_exact_mid = 0.664 / std::sqrt(re1 * 0.5);
  r.exact_force = 0.664 * q * 0.025 * 2 / std::sqrt(re1) * (std::sqrt(0.75) - std::sqrt(0.25));
  // One exchange: the loads at the shell's load points, and both sides' resultants.
  std::vector<double> loads(4 * s.shell->load_points().size());
  const std::size_t n = s.shell->load_points().size();
  s.aerodynamics->pressure_rise(s.solver->displacement(), s.solver->velocity(), std::span(loads).first(n));
  std::vector<Vec3> point_shear(n);
  s.aerodynamics->shear(point_shear);
  for (std::size_t k = 0; k < n; ++k)
    for (std::size_t d = 0; d < 3; ++d) loads[n + 3 * k + d] = point_shear[k][Eigen::Index(d)];
  r.shell_force = s.driver->shell_side_force(loads).x();
  r.fluid_force = s.aerodynamics->fluid_side_force()->x();
  std::printf(
      "Boundary layer (size factor %.1f): %d local-step iterations (d(rho)/dt %.2e); cf at mid-panel %.4e "
      "(Blasius-Chapman-Rubesin %.4e, %+.2f %%); shear force on the panel: fluid %.7f N, shell %.7f N, integral of "
      "the flat-plate cf %.5f N (%+.2f %%)\n",
      size_factor, r.iterations, r.rate, r.cf_mid, r.cf_exact_mid, 100 * (r.cf_mid / r.cf_exact_mid - 1), r.fluid_force,
      r.shell_force, r.exact_force, 100 * (r.shell_force / r.exact_force - 1));
  return r;
}

TEST(ViscousCoupling, LaminarBoundaryLayerSkinFrictionAndShearOnTheShellMatchTheFlatPlateSolution) {
  // The case's mesh (first cell 0.21 mm, ~15 cells in the layer at mid-panel). The wall shear
  // at mid-panel converges geometrically (x0.35 per 2 000 iterations): after 16 000 it is
  // 0.12 % above its value after 24 000 (measured 2026-12-07), far inside the 5 % asserted.
  const BoundaryLayer r = boundary_layer(1.0, 16000);
  EXPECT_NEAR(r.cf_mid / r.cf_exact_mid, 1.0, 0.05);      // measured -3.2 %
  EXPECT_NEAR(r.shell_force / r.exact_force, 1.0, 0.05);  // measured -3.3 %
  // The shear passes whole, to the load points' quadrature of the piecewise-linear shear over
  // shell elements that do not conform to the fluid faces (measured 1e-6).
  EXPECT_NEAR(r.shell_force / r.fluid_force, 1.0, 1e-5);
}

TEST(ViscousCoupling, LaminarBoundaryLayerOnTheCoarseVariantIsFirstOrderFartherOff) {
  // size_factor 2: half the cells each way, the first cell twice as thick: the one-sided
  // truncation of the layer's resolution doubles (the error is first order in the cell).
  // After 10 000 iterations the shear is within 0.07 % of its value after 16 000.
  const BoundaryLayer r = boundary_layer(2.0, 10000);
  EXPECT_NEAR(r.cf_mid / r.cf_exact_mid, 1.0, 0.10);      // measured -7.5 %
  EXPECT_NEAR(r.shell_force / r.exact_force, 1.0, 0.10);  // measured -7.5 %
  EXPECT_NEAR(r.shell_force / r.fluid_force, 1.0, 1e-5);  // measured 2e-6
}

}  // namespace
}  // namespace shellflow::coupling
