// Coupling iterations and their acceleration (coupling/acceleration.h, coupling_iterations.h):
// convergence on linear fixed points with known answers, the checkpoint of the acceleration's
// history, the theory of the explicit staggered scheme's added-mass instability, and the 1-D
// piston problem with an exact solution (docs/coupling.md, "Implicit coupling").
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "shellflow/core/archive.h"
#include "shellflow/coupling/coupling_iterations.h"

namespace shellflow::coupling {
namespace {

using Outcome = CouplingIterations::Outcome;

CouplingIterationOptions options(AccelerationType type, int iterations, double tolerance = 1e-12) {
  CouplingIterationOptions o;
  o.max_iterations = iterations;
  o.tolerance = tolerance;
  o.acceleration.type = type;
  return o;
}

/// H(x) = A x + b with a random A of spectral radius `radius` (n = 20): the plain fixed point
/// diverges for radius > 1, a quasi-Newton method finds x = (I - A)^-1 b in about n iterations.
struct LinearMap {
  Eigen::MatrixXd A;
  Eigen::VectorXd b, solution;
  LinearMap(int n, double radius, unsigned seed) {
    std::mt19937 gen(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    A = Eigen::MatrixXd::NullaryExpr(n, n, [&] { return u(gen); });
    A = 0.5 * (A + A.transpose()).eval();  // real eigenvalues, none at 1 after scaling
    A *= radius / A.eigenvalues().cwiseAbs().maxCoeff();
    b = Eigen::VectorXd::NullaryExpr(n, [&] { return u(gen); });
    solution = (Eigen::MatrixXd::Identity(n, n) - A).lu().solve(b);
  }
  std::vector<double> operator()(std::span<const double> x) const {
    const Eigen::VectorXd y = A * Eigen::Map<const Eigen::VectorXd>(x.data(), Eigen::Index(x.size())) + b;
    return {y.data(), y.data() + y.size()};
  }
};

struct Solve {
  Outcome outcome;
  int iterations;
  std::vector<double> x;
};

Solve solve(CouplingIterations& it, const LinearMap& H, std::vector<double> guess) {
  it.begin(guess);
  for (;;) {
    const std::vector<double> x(it.applied().begin(), it.applied().end());
    const Outcome o = it.result(H(x));
    if (o != Outcome::again) return {o, it.iteration(), x};
  }
}

double error(const std::vector<double>& x, const Eigen::VectorXd& exact) {
  return (Eigen::Map<const Eigen::VectorXd>(x.data(), Eigen::Index(x.size())) - exact).norm() / exact.norm();
}

TEST(Acceleration, IqnIlsSolvesALinearFixedPointThatThePlainIterationCannot) {
  const LinearMap H(20, 1.8, 7);
  const std::vector<double> w(20, 1.0), zero(20, 0.0);
  for (const auto type : {AccelerationType::none, AccelerationType::constant, AccelerationType::aitken}) {
    CouplingIterations it(options(type, 60), w);
    EXPECT_EQ(solve(it, H, zero).outcome, Outcome::not_converged) << to_string(type);
  }
  CouplingIterations iqn(options(AccelerationType::iqn_ils, 60), w);
  const Solve s = solve(iqn, H, zero);
  std::printf("IQN-ILS, n = 20, spectral radius 1.8: %d iterations, error %.2e\n", s.iterations,
              error(s.x, H.solution));
  ASSERT_EQ(s.outcome, Outcome::done);
  EXPECT_LE(s.iterations, 20 + 3);  // a secant method on an affine map: at most n + 2 in exact arithmetic
  EXPECT_LT(error(s.x, H.solution), 1e-10);
}

TEST(Acceleration, IqnIlsReusesThePastWindowsColumns) {
  // The same affine map in every window (only b changes, as a shell step's loads do): with
  // the past windows' columns, the next windows need far fewer iterations than the first.
  LinearMap H(20, 0.9, 11);
  const std::vector<double> w(20, 1.0), zero(20, 0.0);
  auto o = options(AccelerationType::iqn_ils, 60, 1e-10);
  o.acceleration.reuse = 4;
  CouplingIterations it(o, w);
  const int first = solve(it, H, zero).iterations;
  H.b *= 1.3;
  const int second = solve(it, H, zero).iterations;
  std::printf("IQN-ILS windows: %d then %d iterations\n", first, second);
  EXPECT_LE(second, 3);
  EXPECT_GT(first, second);
}

TEST(Acceleration, AitkenIsExactOnAScalarAffineMapAndConstantRelaxationContracts) {
  // x = -3 x + 4: the plain iteration diverges (factor -3); the secant step is exact, so
  // Aitken lands on x = 1 at its third evaluation; w = 0.25 makes it exact in one step.
  struct Scalar {
    std::vector<double> operator()(std::span<const double> x) const { return {-3.0 * x[0] + 4.0}; }
  };
  const std::vector<double> w{1.0}, guess{0.0};
  auto o = options(AccelerationType::aitken, 10);
  o.acceleration.relaxation = 0.1;
  CouplingIterations aitken(o, w);
  aitken.begin(guess);
  Outcome out = Outcome::again;
  while (out == Outcome::again) out = aitken.result(Scalar{}(aitken.applied()));
  EXPECT_EQ(out, Outcome::done);
  EXPECT_LE(aitken.iteration(), 3);
  EXPECT_NEAR(aitken.applied()[0], 1.0, 1e-12);
  o.acceleration.type = AccelerationType::constant;
  o.acceleration.relaxation = 0.25;
  CouplingIterations constant(o, w);
  constant.begin(guess);
  EXPECT_EQ(constant.result(Scalar{}(constant.applied())), Outcome::again);
  EXPECT_DOUBLE_EQ(constant.applied()[0], 1.0);
}

TEST(Acceleration, TheResidualIsWeightedByTheLoadPointsAreas) {
  // A wrong value at a point of zero area does not count; the relative residual is that of
  // the pressure field.
  CouplingIterations it(options(AccelerationType::none, 5, 1e-3), {0.0, 2.0});
  it.begin(std::vector<double>{100.0, 1.0});
  EXPECT_EQ(it.result(std::vector<double>{0.0, 1.0}), Outcome::done);
  EXPECT_EQ(it.residual(), 0.0);
  it.begin(std::vector<double>{0.0, 1.0});
  EXPECT_EQ(it.result(std::vector<double>{0.0, 2.0}), Outcome::again);
  EXPECT_DOUBLE_EQ(it.residual(), 0.5);
  it.begin(std::vector<double>{0.0, 1.0});
  EXPECT_EQ(it.result(std::vector<double>{0.0, NAN}), Outcome::diverged);
}

TEST(Acceleration, EachBlockOfPressureAndShearConvergesOnItsOwnScale) {
  // The interface vector of a viscous flow: 10 pressures of 1e5 Pa, then 30 shear components
  // of 1 Pa that follow the pressure (and themselves, diverging under the plain iteration).
  // H = D A D^-1 x + D b with D = diag(1e5, 1): the shear block's own residual is 1e-5 of the
  // whole vector's, so a test of the whole would stop with the shear unconverged.
  const int np = 10, ns = 30, n = np + ns;
  LinearMap H(n, 1.3, 11);
  H.A.topRightCorner(np, ns).setZero();  // the pressure does not depend on the shear
  Eigen::VectorXd d = Eigen::VectorXd::Ones(n);
  d.head(np).setConstant(1e5);
  H.A = d.asDiagonal() * H.A * d.cwiseInverse().asDiagonal();
  H.b = d.cwiseProduct(H.b);
  H.solution = (Eigen::MatrixXd::Identity(n, n) - H.A).lu().solve(H.b);
  const std::vector<double> w(n, 1.0), zero(n, 0.0);
  const auto block_error = [&](const Solve& s, int from, int size) {
    const Eigen::Map<const Eigen::VectorXd> x(s.x.data(), n);
    return (x.segment(from, size) - H.solution.segment(from, size)).norm() / H.solution.segment(from, size).norm();
  };
  for (const auto type : {AccelerationType::aitken, AccelerationType::iqn_ils}) {
    SCOPED_TRACE(std::string(to_string(type)));
    CouplingIterations whole(options(type, 200, 1e-8), w);
    CouplingIterations blocks(options(type, 200, 1e-8), w, {std::size_t(np), std::size_t(ns)});
    const Solve a = solve(whole, H, zero), b = solve(blocks, H, zero);
    std::printf("%s: one block: %s after %d iterations, shear error %.2e; two blocks: %s after %d, shear error %.2e\n",
                std::string(to_string(type)).c_str(), a.outcome == Outcome::done ? "done" : "not converged",
                a.iterations, block_error(a, np, ns), b.outcome == Outcome::done ? "done" : "not converged",
                b.iterations, block_error(b, np, ns));
    // Measured: Aitken 41 iterations and a shear error of 1.7e-3 with one block, 78 and 4.6e-8
    // with two; IQN-ILS 20 and 1.3e-4, 29 and 3.9e-9.
    ASSERT_EQ(b.outcome, Outcome::done);
    EXPECT_LE(block_error(b, 0, np), 1e-6);
    EXPECT_LE(block_error(b, np, ns), 1e-6);
    // The whole vector's test passes with the shear far from its answer.
    ASSERT_EQ(a.outcome, Outcome::done);
    EXPECT_GE(block_error(a, np, ns), 5e-5);
    EXPECT_GE(block_error(a, np, ns), 1e3 * block_error(b, np, ns));
  }
  // The residual reported is the worst block's.
  CouplingIterations it(options(AccelerationType::none, 5, 1e-3), {1.0, 1.0}, {1, 1});
  it.begin(std::vector<double>{1e5, 1.0});
  EXPECT_EQ(it.result(std::vector<double>{1e5, 2.0}), Outcome::again);
  EXPECT_DOUBLE_EQ(it.residual(), 0.5);
}

TEST(Acceleration, RestoreThenIterateEqualsIterateBitForBit) {
  // Windows 1-3 on one object; a second object restored from the checkpoint after window 2
  // repeats window 3 bit for bit (the IQN-ILS columns of past windows, Aitken's factor).
  for (const auto type : {AccelerationType::aitken, AccelerationType::iqn_ils}) {
    const LinearMap H(12, 0.95, 3);
    const std::vector<double> w(12, 0.5);
    auto o = options(type, 200, 1e-11);
    o.acceleration.reuse = 2;
    CouplingIterations a(o, w);
    std::vector<double> guess(12, 0.0);
    solve(a, H, guess);
    guess[3] = 1.0;
    solve(a, H, guess);
    ArchiveWriter out;
    a.save(out);
    guess[5] = -2.0;
    const Solve straight = solve(a, H, guess);
    CouplingIterations b(o, w);
    ArchiveReader in(out.bytes(), "test");
    b.restore(in);
    const Solve restored = solve(b, H, guess);
    EXPECT_EQ(straight.iterations, restored.iterations) << to_string(type);
    EXPECT_EQ(straight.x, restored.x) << to_string(type);
  }
}

TEST(Acceleration, TheExplicitSchemesBlowUpMonitor) {
  // Loads that flip sign every step and grow 1.5-fold per step: diverged as soon as the
  // monitor looks (step 20: the predictor misses by 2.3 times the load, which is 58 times
  // its peak before the last ten steps); the same loads at the round-off level (below
  // noise_pressure) are left alone, as are smoothly growing loads.
  auto o = options(AccelerationType::none, 1);
  o.noise_pressure = 1e-6;
  const auto steps_to_blow_up = [&](double scale, bool alternate) {
    CouplingIterations it(o, {1.0, 1.0});
    double previous = 0.0;
    for (int n = 1; n <= 100; ++n) {
      const double load = scale * std::pow(1.5, n) * (alternate && n % 2 ? -1.0 : 1.0);
      it.begin(std::vector<double>{2 * previous, 2 * previous});  // whatever the predictor says
      previous = load;
      if (it.result(std::vector<double>{load, load}) == Outcome::diverged) return n;
    }
    return 0;
  };
  EXPECT_EQ(steps_to_blow_up(1e-3, true), 20);
  EXPECT_EQ(steps_to_blow_up(1e-30, true), 0);  // 1e-30 x 1.5^100 = 4e-13 < 1e-6
  EXPECT_EQ(steps_to_blow_up(1e-3, false), 0);
}

TEST(StaggeredStability, CriticalAddedMassRatios) {
  // Resolved modes (omega dt -> 0): the loose scheme is stable for rho c dt / m < 2 without
  // a predictor, < 2/sqrt(3) with the linear one.
  EXPECT_NEAR(staggered_critical_ratio(LoadPredictor::none, 1e-3), 2.0, 1e-5);
  EXPECT_NEAR(staggered_critical_ratio(LoadPredictor::linear, 1e-3), 2.0 / std::sqrt(3.0), 1e-5);
  // Radius just below / above the limit.
  EXPECT_LE(staggered_spectral_radius(1.9, 0.05, LoadPredictor::none), 1.0);
  EXPECT_GT(staggered_spectral_radius(2.1, 0.05, LoadPredictor::none), 1.0);
}

// --- the 1-D piston problem -------------------------------------------------------------
//
// A piston of mass m per area on a spring k per area, facing a column of gas (density rho,
// sound speed c) at rest, open at its far end (non-reflecting: no wave comes back), so the
// acoustic solution is exact: the gas pushes back with p' = rho c v (the outgoing
// simple wave), and m x'' + rho c x' + k x = 0 decays at rate rho c / (2 m) with frequency
// sqrt(k/m - (rho c / 2m)^2). The test's fluid is a real wave solver (linear acoustics,
// characteristic upwinding at Courant number 1, sub-cycled inside the shell step with the
// piston's velocity interpolated in time), the piston a Newmark trapezoidal step as the
// shell's; the coupling is the partitioned driver's loop with CouplingIterations.

class AcousticColumn {
 public:
  /// `cells` cells of length c dt_fluid, `substeps` fluid steps per shell step.
  AcousticColumn(double rho, double c, int cells, int substeps)
      : impedance_(rho * c), substeps_(substeps), plus_(std::size_t(cells) + 1, 0.0), minus_(plus_) {}
  /// Advance one shell step with the piston's velocity v(t) = v0 + (v1 - v0) s (s in [0, 1]:
  /// the window's interpolation); returns the pressure rise at the piston at the step's end.
  double advance(double v0, double v1) {
    const std::size_t n = plus_.size();
    for (int j = 1; j <= substeps_; ++j) {
      const double v = v0 + (v1 - v0) * double(j) / substeps_;
      // Riemann invariants w+ = p + Z u (to the right) and w- = p - Z u (to the left) move
      // one cell per step at Courant 1 (ring buffers: node i of w+ is plus_[(head + i) % n]);
      // the far end lets w+ out and sends no w- in.
      plus_head_ = (plus_head_ + n - 1) % n;
      minus_[minus_head_] = 0.0;  // the old node 0 of w- becomes the new far-end node
      minus_head_ = (minus_head_ + 1) % n;
      // At the piston u = v: w+ = w- + 2 Z v.
      plus_[plus_head_] = minus_[minus_head_] + 2.0 * impedance_ * v;
    }
    return 0.5 * (plus_[plus_head_] + minus_[minus_head_]);
  }
  struct Mark {
    std::vector<double> plus, minus;
    std::size_t plus_head, minus_head;
  };
  Mark mark() const { return {plus_, minus_, plus_head_, minus_head_}; }
  void rewind(const Mark& m) { plus_ = m.plus, minus_ = m.minus, plus_head_ = m.plus_head, minus_head_ = m.minus_head; }

 private:
  double impedance_;
  int substeps_;
  std::vector<double> plus_, minus_;
  std::size_t plus_head_ = 0, minus_head_ = 0;
};

struct PistonRun {
  bool completed = true;       ///< false: the coupling iterations failed (not converged / diverged)
  double decay = 0.0;          ///< fitted decay rate, 1/s
  double amplification = 0.0;  ///< of the loads' second difference: last quarter / second quarter
  double mean_iterations = 0.0;
  double final_x = 0.0;
};

/// m = 1 per area, omega0 = 1 rad/s; dt from omega0 dt; the ratio rho c dt / m sets rho c.
PistonRun piston_run(double ratio, double omega_dt, LoadPredictor predictor, const CouplingIterationOptions& o,
                     int steps) {
  const double m = 1.0, k = 1.0, dt = omega_dt, z = ratio * m / dt;
  constexpr int substeps = 8;
  AcousticColumn gas(z, 1.0, 4 * substeps, substeps);
  CouplingIterations it(o, {1.0});
  double x = 1.0, v = 0.0, a = -k * x / m, p = 0.0, p_previous = 0.0;
  bool has_previous = false;
  std::vector<double> xs{x}, ps{0.0};
  PistonRun run;
  for (int n = 0; n < steps; ++n) {
    const AcousticColumn::Mark mark = gas.mark();
    const double guess = predictor == LoadPredictor::linear && has_previous ? 2 * p - p_previous : p;
    it.begin(std::vector<double>{guess});
    double x1 = 0, v1 = 0, a1 = 0, p1 = 0;
    for (;;) {
      const double f = -it.applied()[0];  // the gas pushes the piston back
      a1 = (f - k * (x + dt * v + 0.25 * dt * dt * a)) / (m + 0.25 * k * dt * dt);
      x1 = x + dt * v + 0.25 * dt * dt * (a + a1);
      v1 = v + 0.5 * dt * (a + a1);
      p1 = gas.advance(v, v1);
      const Outcome out = it.result(std::vector<double>{p1});
      if (out == Outcome::done) break;
      if (out != Outcome::again) return {false, 0, 0, 0};
      gas.rewind(mark);
    }
    run.mean_iterations += it.iteration();
    p_previous = p;
    p = p1;
    has_previous = true;
    x = x1, v = v1, a = a1;
    xs.push_back(x);
    ps.push_back(p);
    if (!std::isfinite(x) || std::abs(x) > 1e12) return {false, 0, 0, 0};
  }
  run.mean_iterations /= steps;
  run.final_x = x;
  // Decay: least-squares slope of log|x| at the extrema of x (underdamped runs).
  std::vector<double> te, le;
  for (std::size_t i = 1; i + 1 < xs.size(); ++i)
    if (std::abs(xs[i]) >= std::abs(xs[i - 1]) && std::abs(xs[i]) >= std::abs(xs[i + 1]) && xs[i] != 0.0) {
      te.push_back(double(i) * dt);
      le.push_back(std::log(std::abs(xs[i])));
    }
  if (te.size() >= 3) {
    double st = 0, sl = 0, stt = 0, stl = 0;
    const double nn = double(te.size());
    for (std::size_t i = 0; i < te.size(); ++i) st += te[i], sl += le[i], stt += te[i] * te[i], stl += te[i] * le[i];
    run.decay = -(nn * stl - st * sl) / (nn * stt - st * st);
  }
  // The loose scheme's instability is a mode of period ~2 dt in the loads: their second
  // difference filters out the smooth physical motion, whose slow overdamped decay would hide
  // a slow growth near the limit.
  double second = 0.0, last = 0.0;
  for (std::size_t i = 2; i < ps.size(); ++i) {
    const double d = std::abs(ps[i] - 2 * ps[i - 1] + ps[i - 2]);
    if (4 * i >= ps.size() && 4 * i < 2 * ps.size()) second = std::max(second, d);
    if (4 * i >= 3 * ps.size()) last = std::max(last, d);
  }
  run.amplification = last / second;
  return run;
}

TEST(PistonProblem, BelowTheLimitEverySchemeGivesTheExactDecay) {
  // rho c dt / m = 0.01 at omega0 dt = 0.05: damping ratio 0.1, exact decay rate rho c / 2m.
  const double ratio = 0.01, omega_dt = 0.05, exact = ratio / omega_dt / 2.0;
  struct Scheme {
    const char* name;
    LoadPredictor predictor;
    CouplingIterationOptions o;
  };
  const Scheme schemes[] = {
      {"loose, no predictor", LoadPredictor::none, options(AccelerationType::none, 1)},
      {"loose, linear predictor", LoadPredictor::linear, options(AccelerationType::none, 1)},
      {"implicit, none", LoadPredictor::linear, options(AccelerationType::none, 50, 1e-10)},
      {"implicit, aitken", LoadPredictor::linear, options(AccelerationType::aitken, 50, 1e-10)},
      {"implicit, iqn_ils", LoadPredictor::linear, options(AccelerationType::iqn_ils, 50, 1e-10)},
  };
  for (const Scheme& s : schemes) {
    const PistonRun run = piston_run(ratio, omega_dt, s.predictor, s.o, 1200);
    std::printf("%-26s decay %.5f 1/s (exact %.5f, %+.3f %%), %.2f iterations/step\n", s.name, run.decay, exact,
                100 * (run.decay / exact - 1), run.mean_iterations);
    ASSERT_TRUE(run.completed) << s.name;
    EXPECT_NEAR(run.decay, exact, 0.02 * exact) << s.name;
  }
}

TEST(PistonProblem, TheLooseSchemesLimitFromRunsMatchesTheTheory) {
  // Bisection on the ratio with runs of 4000 steps: unstable when the loads' parasitic
  // oscillation is larger in the last quarter of the run than in the second.
  const double omega_dt = 0.05;
  for (const auto predictor : {LoadPredictor::none, LoadPredictor::linear}) {
    double lo = 0.5, hi = 3.0;
    for (int i = 0; i < 30; ++i) {
      const double mid = 0.5 * (lo + hi);
      const PistonRun run = piston_run(mid, omega_dt, predictor, options(AccelerationType::none, 1), 4000);
      (run.completed && run.amplification < 1.0 ? lo : hi) = mid;
    }
    const double theory = staggered_critical_ratio(predictor, omega_dt);
    std::printf("loose staggered, %s predictor: critical rho c dt/m from runs %.4f, theory %.4f\n",
                predictor == LoadPredictor::none ? "no" : "linear", lo, theory);
    EXPECT_NEAR(lo, theory, 0.005 * theory);
  }
}

TEST(PistonProblem, AboveTheLimitAitkenAndIqnIlsConvergeToTheImplicitSolution) {
  // rho c dt / m = 3 (1.5 x the loose limit): the plain fixed point has factor ~ -1.5 and
  // fails; Aitken and IQN-ILS converge every step, and the run is the monolithic Newmark
  // solution of m x'' + rho c x' + k x = 0 (overdamped here).
  const double ratio = 3.0, omega_dt = 0.05, dt = omega_dt, z = ratio / dt;
  EXPECT_FALSE(piston_run(ratio, omega_dt, LoadPredictor::linear, options(AccelerationType::none, 1), 400).completed);
  EXPECT_FALSE(
      piston_run(ratio, omega_dt, LoadPredictor::linear, options(AccelerationType::none, 30, 1e-10), 400).completed);
  // Monolithic Newmark with the damper: (m + z dt/2 + k dt^2/4) a1 = -k (x + dt v + dt^2 a/4) - z (v + dt a/2).
  double x = 1.0, v = 0.0, a = -x;
  for (int n = 0; n < 400; ++n) {
    const double a1 =
        (-(x + dt * v + 0.25 * dt * dt * a) - z * (v + 0.5 * dt * a)) / (1.0 + 0.5 * z * dt + 0.25 * dt * dt);
    x += dt * v + 0.25 * dt * dt * (a + a1);
    v += 0.5 * dt * (a + a1);
    a = a1;
  }
  for (const auto type : {AccelerationType::aitken, AccelerationType::iqn_ils}) {
    const PistonRun run = piston_run(ratio, omega_dt, LoadPredictor::linear, options(type, 30, 1e-10), 400);
    std::printf("%s at ratio 3: %.2f iterations/step\n", std::string(to_string(type)).c_str(), run.mean_iterations);
    ASSERT_TRUE(run.completed) << to_string(type);
    EXPECT_LT(run.mean_iterations, 6.0) << to_string(type);
    EXPECT_NEAR(run.final_x, x, 1e-8 * std::abs(x)) << to_string(type);
  }
}

}  // namespace
}  // namespace shellflow::coupling
