// Oblique shock on a compression ramp at Mach 2.5 (fluid-references.md b1), steady state
// of the quasi-2-D slab against the theta–beta–M relation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <utility>
#include <vector>

#include "fluid_test_util.h"
#include "oblique_shock.h"

using namespace shellflow;
using namespace shellflow::fluid;

namespace {

constexpr double deg = std::numbers::pi / 180.0;

struct RampResult {
  double wall_pressure_ratio, beta_deg;
};

/// Global steps to t_end, or (local = true) `local_steps` local steps.
RampResult run_ramp(int theta_deg, double t_end, bool local = false, int local_steps = 0) {
  const double gamma = 1.4, mach = 2.5;
  const Primitive free_stream{1.0, Vec3(mach, 0.0, 0.0), 1.0 / gamma};  // c = 1
  FluidOptions o;
  o.q_dif = 1.0;
  FluidModel model(test_support::case_mesh("ramp_" + std::to_string(theta_deg) + "deg.geo"), o,
                   {{"inflow", BoundaryKind::supersonic_inflow, free_stream, {}},
                    {"top", BoundaryKind::supersonic_inflow, free_stream, {}},
                    {"outflow", BoundaryKind::supersonic_outflow, {}, {}},
                    {"wall", BoundaryKind::slip_wall, {}, {}},
                    {"symmetry", BoundaryKind::symmetry, {}, {}}});
  model.set_state([&](const Vec3&) { return free_stream; });
  if (local) {
    const double initial_rate = [&] {
      model.step_local(0.5);
      return model.density_rate();
    }();
    for (int n = 1; n < local_steps; ++n) model.step_local(0.5);
    std::printf("local time stepping: %d steps, d(rho)/dt RMS %.3e -> %.3e\n", local_steps, initial_rate,
                model.density_rate());
  } else {
    test_support::run_until(model, t_end, 0.5);
  }

  const double p1 = free_stream.pressure;
  const double p2 = test_support::oblique_shock(mach, theta_deg * deg, gamma).pressure_ratio * p1;
  RampResult r{};
  // Mean wall pressure on the ramp, 0.3 <= x <= 0.9.
  double sum = 0.0;
  int count = 0;
  for (const Index a : model.mesh().group("wall").nodes) {
    const Vec3& x = model.positions()[std::size_t(a)];
    if (x.x() >= 0.3 && x.x() <= 0.9) {
      sum += model.primitive(a).pressure;
      ++count;
    }
  }
  r.wall_pressure_ratio = sum / count / p1;
  // Shock angle: first crossing of p = (p1 + p2)/2 along the line y = 0.3, z = 0, sampled
  // where the line cuts mesh edges (p linear along each edge) and interpolated between
  // consecutive samples.
  const double level = 0.5 * (p1 + p2);
  std::vector<std::pair<double, double>> samples;  // (x, p)
  const auto& cells = model.mesh().cells;
  for (Index e = 0; e < cells.size(); ++e) {
    const auto n = cells.element(e);
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        const Vec3& xa = model.positions()[std::size_t(n[std::size_t(i)])];
        const Vec3& xb = model.positions()[std::size_t(n[std::size_t(j)])];
        if (std::abs(xa.z()) > 1e-12 || std::abs(xb.z()) > 1e-12) continue;
        if ((xa.y() - 0.3) * (xb.y() - 0.3) > 0 || xa.y() == xb.y()) continue;
        const double f = (0.3 - xa.y()) / (xb.y() - xa.y());
        samples.emplace_back(xa.x() + f * (xb.x() - xa.x()), (1 - f) * model.primitive(n[std::size_t(i)]).pressure +
                                                                 f * model.primitive(n[std::size_t(j)]).pressure);
      }
  }
  std::sort(samples.begin(), samples.end());
  double x_cross = 1e9;
  for (std::size_t k = 1; k < samples.size(); ++k) {
    const auto [xa, pa] = samples[k - 1];
    const auto [xb, pb] = samples[k];
    if (xa > 0.0 && pa < level && pb >= level) {
      x_cross = xa + (level - pa) / (pb - pa) * (xb - xa);
      break;
    }
  }
  r.beta_deg = std::atan2(0.3, x_cross) / deg;
  return r;
}

void check_ramp(int theta) {
  const auto exact = test_support::oblique_shock(2.5, theta * deg);
  const auto r = run_ramp(theta, 2.0);
  std::printf(
      "ramp %d deg: wall p2/p1 = %.5f (exact %.5f, %+.3f%%), beta = %.3f deg "
      "(exact %.3f, %+.3f deg)\n",
      theta, r.wall_pressure_ratio, exact.pressure_ratio, 100 * (r.wall_pressure_ratio / exact.pressure_ratio - 1),
      r.beta_deg, exact.beta / deg, r.beta_deg - exact.beta / deg);
  EXPECT_NEAR(r.wall_pressure_ratio / exact.pressure_ratio, 1.0, 0.015);
  EXPECT_NEAR(r.beta_deg, exact.beta / deg, 0.7);
}

}  // namespace

TEST(CompressionRamp, ThetaBetaMachOracleReproducesTheReferenceTable) {
  const auto s10 = test_support::oblique_shock(2.5, 10 * deg);
  const auto s15 = test_support::oblique_shock(2.5, 15 * deg);
  EXPECT_NEAR(s10.beta / deg, 31.8506, 1e-4);
  EXPECT_NEAR(s10.pressure_ratio, 1.863871, 1e-6);
  EXPECT_NEAR(s15.beta / deg, 36.9449, 1e-4);
  EXPECT_NEAR(s15.pressure_ratio, 2.467500, 1e-6);
}

TEST(CompressionRamp, Mach25At10DegreesMatchesTheObliqueShock) { check_ramp(10); }
TEST(CompressionRamp, Mach25At15DegreesMatchesTheObliqueShock) { check_ramp(15); }

TEST(CompressionRamp, LocalTimeSteppingReachesTheSameSteadyState) {
  const auto exact = test_support::oblique_shock(2.5, 15 * deg);
  const auto r = run_ramp(15, 0.0, true, 1500);
  std::printf("ramp 15 deg, local steps: wall p2/p1 = %.5f (%+.3f%%), beta = %.3f deg (%+.3f)\n", r.wall_pressure_ratio,
              100 * (r.wall_pressure_ratio / exact.pressure_ratio - 1), r.beta_deg, r.beta_deg - exact.beta / deg);
  EXPECT_NEAR(r.wall_pressure_ratio / exact.pressure_ratio, 1.0, 0.015);
  EXPECT_NEAR(r.beta_deg, exact.beta / deg, 0.7);
}
