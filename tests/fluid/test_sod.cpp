// Shock tubes (fluid-references.md a1 Sod, a2 Lax) on the quasi-1-D tetrahedral tube at
// three resolutions, against the exact Riemann solution: L1(rho), observed order, plateau
// pressure, shock position. The reflection of a shock from a closed end against the normal
// reflection (issue 37).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <vector>

#include "exact_riemann.h"
#include "fluid_test_util.h"

using namespace shellflow;
using namespace shellflow::fluid;
using shellflow::fluid::test_support::ExactRiemann;
using shellflow::fluid::test_support::State1d;

namespace {

const State1d sod_left{1.0, 0.0, 1.0};
const State1d sod_right{0.125, 0.0, 0.1};
constexpr double cfl = 0.5;

/// A Riemann problem on [0, 1] with the diaphragm at 0.5, and the window [lo, hi] between
/// the rarefaction tail and the shock where the exact pressure is p*.
/// Ends: slip walls (Sod: no wave reaches them), or a characteristic far field holding the
/// initial states (Lax: the left gas moves, a wall there would send a rarefaction in).
struct RiemannCase {
  State1d left, right;
  double t_end, plateau_lo, plateau_hi;
  BoundaryKind ends;
};
const RiemannCase sod{sod_left, sod_right, 0.2, 0.52, 0.82, BoundaryKind::slip_wall};
const RiemannCase lax{{0.445, 0.698, 3.528}, {0.5, 0.0, 0.571}, 0.14, 0.30, 0.82, BoundaryKind::far_field};

Primitive primitive(const State1d& s) { return {s.rho, Vec3(s.u, 0.0, 0.0), s.p}; }
constexpr double q_dif = 1.0;

struct AxisProfile {
  std::vector<double> x, rho, p;  // averaged over the nodes of each cross-section
};

AxisProfile axis_profile(const FluidModel& model) {
  std::map<long, std::array<double, 4>> sums;  // key: x in units of 1e-9
  for (Index a = 0; a < model.mesh().num_nodes(); ++a) {
    const double x = model.positions()[std::size_t(a)].x();
    const Primitive s = model.primitive(a);
    auto& v = sums[std::lround(x * 1e9)];
    v[0] += x;
    v[1] += s.rho;
    v[2] += s.pressure;
    v[3] += 1;
  }
  AxisProfile out;
  for (const auto& [key, v] : sums) {
    out.x.push_back(v[0] / v[3]);
    out.rho.push_back(v[1] / v[3]);
    out.p.push_back(v[2] / v[3]);
  }
  return out;
}

struct SodResult {
  double l1_rho, plateau_p, shock_x, h, max_overshoot;
};

SodResult run_riemann(const RiemannCase& rc, int nx) {
  auto mesh = test_support::case_mesh("tube_nx" + std::to_string(nx) + ".geo");
  FluidOptions options;
  options.gas.gamma = 1.4;
  options.q_dif = q_dif;
  std::vector<BoundaryCondition> bcs = {{"left", rc.ends, primitive(rc.left), {}},
                                        {"right", rc.ends, primitive(rc.right), {}},
                                        {"sides", BoundaryKind::symmetry, {}, {}}};
  FluidModel model(std::move(mesh), options, bcs);
  model.set_state([&](const Vec3& x) {
    const State1d s = x.x() < 0.5 - 1e-12   ? rc.left
                      : x.x() > 0.5 + 1e-12 ? rc.right
                                            : State1d{0.5 * (rc.left.rho + rc.right.rho),
                                                      0.5 * (rc.left.u + rc.right.u), 0.5 * (rc.left.p + rc.right.p)};
    return Primitive{s.rho, Vec3(s.u, 0.0, 0.0), s.p};
  });
  test_support::run_until(model, rc.t_end, cfl);

  const ExactRiemann exact(rc.left, rc.right);
  const double t_end = rc.t_end;
  const AxisProfile prof = axis_profile(model);
  SodResult r{};
  r.h = 1.0 / nx;
  double plateau = 0.0;
  int n_plateau = 0;
  for (std::size_t i = 0; i < prof.x.size(); ++i) {
    const double x = prof.x[i];
    const double err = std::abs(prof.rho[i] - exact.sample((x - 0.5) / t_end).rho);
    const double w = (i == 0 || i + 1 == prof.x.size()) ? 0.5 : 1.0;  // trapezoid
    r.l1_rho += w * err * r.h;
    if (x > rc.plateau_lo && x < rc.plateau_hi) {
      plateau += prof.p[i];
      ++n_plateau;
    }
    // Exact p <= p* right of the rarefaction tail (plateau and the undisturbed gas), so
    // any excess there is an overshoot of the scheme.
    if (x > rc.plateau_lo) r.max_overshoot = std::max(r.max_overshoot, (prof.p[i] - exact.p_star()) / exact.p_star());
  }
  r.plateau_p = plateau / n_plateau;
  // Shock: rightmost crossing of the mean of the densities on both sides.
  const double level = 0.5 * (exact.rho_star_right() + rc.right.rho);
  for (std::size_t i = prof.x.size() - 1; i > 0; --i)
    if (prof.rho[i - 1] >= level && prof.rho[i] < level) {
      const double f = (prof.rho[i - 1] - level) / (prof.rho[i - 1] - prof.rho[i]);
      r.shock_x = prof.x[i - 1] + f * (prof.x[i] - prof.x[i - 1]);
      break;
    }
  return r;
}

}  // namespace

TEST(SodShockTube, ExactOracleReproducesTheReferenceValues) {
  const ExactRiemann exact(sod_left, sod_right);
  EXPECT_NEAR(exact.p_star(), 0.3031301781, 1e-9);
  EXPECT_NEAR(exact.u_star(), 0.9274526200, 1e-9);
  EXPECT_NEAR(exact.rho_star_left(), 0.4263194282, 1e-9);
  EXPECT_NEAR(exact.rho_star_right(), 0.2655737117, 1e-9);
  EXPECT_NEAR(exact.right_shock_speed(), 1.7521557320, 1e-9);
  // Fan: continuous at head and tail.
  const double head = -std::sqrt(1.4), tail = 0.4859454375 - 0.5;
  EXPECT_NEAR(exact.sample(head + 1e-12).rho, 1.0, 1e-9);
  EXPECT_NEAR(exact.sample(tail / 0.2 - 1e-12).rho, exact.rho_star_left(), 1e-8);
  const ExactRiemann lax({0.445, 0.698, 3.528}, {0.5, 0.0, 0.571});
  EXPECT_NEAR(lax.p_star(), 2.4660979192, 1e-8);
  EXPECT_NEAR(lax.u_star(), 1.5287230266, 1e-8);
  EXPECT_NEAR(lax.rho_star_left(), 0.3445684742, 1e-8);
  EXPECT_NEAR(lax.rho_star_right(), 1.3040845320, 1e-8);
}

namespace {

/// Runs `rc` at Nx = 100, 200, 400; checks plateau pressure, shock position and overshoot
/// at each, returns the L1(rho) errors.
std::vector<double> convergence_study(const char* name, const RiemannCase& rc) {
  const int resolutions[] = {100, 200, 400};
  std::vector<double> l1;
  const ExactRiemann exact(rc.left, rc.right);
  const double shock_exact = 0.5 + exact.right_shock_speed() * rc.t_end;
  for (const int nx : resolutions) {
    const auto r = run_riemann(rc, nx);
    l1.push_back(r.l1_rho);
    std::printf(
        "%s Nx=%d: L1(rho)=%.5f  plateau p=%.5f (%.3f%%)  shock x=%.5f (%.2f h)  "
        "max p overshoot %.2f%%\n",
        name, nx, r.l1_rho, r.plateau_p, 100 * (r.plateau_p / exact.p_star() - 1), r.shock_x,
        (r.shock_x - shock_exact) / r.h, 100 * r.max_overshoot);
    EXPECT_LT(std::abs(r.plateau_p / exact.p_star() - 1), 0.02) << name << " Nx = " << nx;
    EXPECT_LT(std::abs(r.shock_x - shock_exact), 2 * r.h) << name << " Nx = " << nx;
    EXPECT_LT(r.max_overshoot, 0.10) << name << " Nx = " << nx;
  }
  for (std::size_t i = 1; i < l1.size(); ++i)
    std::printf("%s observed L1 order %d -> %d: %.3f\n", name, resolutions[i - 1], resolutions[i],
                std::log2(l1[i - 1] / l1[i]));
  return l1;
}

}  // namespace

TEST(SodShockTube, ConvergesToTheExactSolutionAtFirstOrderOrBetter) {
  const auto l1 = convergence_study("Sod", sod);
  EXPECT_LE(l1[0], 0.02);
  EXPECT_LE(l1[1], 0.012);
  EXPECT_GE(std::log2(l1[0] / l1[1]), 0.7);
  EXPECT_GE(std::log2(l1[1] / l1[2]), 0.7);
}

TEST(LaxShockTube, ConvergesToTheExactSolution) {
  // No limit in the references; Lax's strong contact smears like h^(1/2) (first order) to
  // h^(2/3) (second order) in L1, so the order bound is 0.5.
  const auto l1 = convergence_study("Lax", lax);
  EXPECT_LE(l1[0], 0.04);
  EXPECT_GE(std::log2(l1[0] / l1[1]), 0.5);
  EXPECT_GE(std::log2(l1[1] / l1[2]), 0.5);
}

TEST(ShockReflection, AShockOnAClosedEndReflectsAtTheNormalReflectionPressure) {
  // The shock of the shock-tube plate experiment (Giordano et al. 2005; issue 37): Mach 1.21
  // into gas at rest, here in units of the pre-shock gas (rho1 = p1 = 1). The Rankine-Hugoniot
  // states behind it, and the normal reflection from a closed end (gas at rest behind the
  // reflected shock):
  //   p2/p1 = 1 + 2 g/(g+1) (M^2 - 1),  rho2/rho1 = (g+1) M^2 / ((g-1) M^2 + 2),
  //   u2 = 2 c1/(g+1) (M - 1/M),  p5/p2 = ((3g-1) M^2 - 2(g-1)) / ((g-1) M^2 + 2).
  const double g = 1.4, M = 1.21, c1 = std::sqrt(g);
  const State1d pre{1.0, 0.0, 1.0};
  const State1d post{(g + 1) * M * M / ((g - 1) * M * M + 2), 2 * c1 / (g + 1) * (M - 1 / M),
                     1 + 2 * g / (g + 1) * (M * M - 1)};
  const double p5 = post.p * ((3 * g - 1) * M * M - 2 * (g - 1)) / ((g - 1) * M * M + 2);
  // The case's dimensional states (rho 1.2 -> 1.63 kg/m3, p 1.01e5 -> 1.557e5 Pa, u 109.6 m/s)
  // are these to their rounding.
  EXPECT_NEAR(post.rho * 1.2, 1.63, 0.005);
  EXPECT_NEAR(post.p * 1.01e5, 1.557e5, 0.001e5);
  EXPECT_NEAR(post.u * std::sqrt(1.01e5 / 1.2), 109.6, 0.5);
  // Two oracles agree: the exact Riemann solver on (post | mirrored post) is the reflection.
  const ExactRiemann incident(post, pre), reflected(post, {post.rho, -post.u, post.p});
  EXPECT_NEAR(incident.p_star(), post.p, 1e-9);
  EXPECT_NEAR(incident.right_shock_speed(), M * c1, 1e-9);
  EXPECT_NEAR(reflected.p_star(), p5, 1e-9);
  EXPECT_NEAR(reflected.u_star(), 0.0, 1e-12);

  // The tube [0, 1] (100 columns): the shock starts at x = 0.5, the inflow x = 0 holds the
  // post-shock state (a subsonic far field), x = 1 is a closed end (slip wall).
  const double h = 0.01, t_hit = 0.5 / (M * c1), w_reflected = -reflected.left_shock_speed();
  const double t_end = t_hit + 0.3 / w_reflected;  // the reflected shock 0.3 from the end
  FluidOptions options;
  options.gas.gamma = g;
  options.q_dif = q_dif;
  FluidModel model(test_support::case_mesh("tube_nx100.geo"), options,
                   {{"left", BoundaryKind::far_field, primitive(post), {}},
                    {"right", BoundaryKind::slip_wall, {}, {}},
                    {"sides", BoundaryKind::symmetry, {}, {}}});
  model.set_state([&](const Vec3& x) { return primitive(x.x() < 0.5 ? post : pre); });
  test_support::run_until(model, t_end, cfl);
  const AxisProfile prof = axis_profile(model);
  const double x_reflected = 1.0 - 0.3;
  double sum = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < prof.x.size(); ++i)
    if (prof.x[i] > x_reflected + 5 * h) {  // the gas at rest between the shock and the end
      sum += prof.p[i];
      ++n;
    }
  // Where the profile's pressure crosses the mean of p2 and p5: the reflected shock.
  double x_shock = 0.0;
  const double level = 0.5 * (post.p + p5);
  for (std::size_t i = 1; i < prof.x.size(); ++i)
    if (prof.p[i - 1] < level && prof.p[i] >= level) {
      x_shock = prof.x[i - 1] + (level - prof.p[i - 1]) / (prof.p[i] - prof.p[i - 1]) * h;
      break;
    }
  std::printf("reflected: p5 %.5f (exact %.5f, %+.3f %%), shock at x = %.4f (exact %.4f, %+.2f h)\n", sum / n, p5,
              100 * (sum / n / p5 - 1), x_shock, x_reflected, (x_shock - x_reflected) / h);
  ASSERT_GT(n, 10);
  // Measured 2026-12-07: p5 -0.008 %, the shock +0.73 h (the start-up of the reflection at the end).
  EXPECT_NEAR(sum / n / p5, 1.0, 1e-3);
  EXPECT_NEAR(x_shock, x_reflected, 1 * h);
}
