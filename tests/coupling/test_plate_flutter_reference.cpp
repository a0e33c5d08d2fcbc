// Tests of the independent plate / shallow-panel flutter reference model (plate_flutter_reference.h): in-vacuo
// frequencies against Leissa (Vibration of Plates, NASA SP-160, 1969) and the exact Navier values, the two-mode
// closed form of the coalescence, Dowell's lambda_cr (Aeroelasticity of plates and shells, 1975: 512 for the simply
// supported square, 343.3 / 636.6 for the pinned / clamped 2-D panel), mode convergence, the curved panel and the
// in-plane condensation, matrix symmetries, and the damped (state-space) variant against a closed-form criterion.
// Material: E = 77.28 GPa, nu = 0.33, rho = 2710 kg/m^3, h = 1.35 mm, a = 0.5 m (streamwise).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <limits>
#include <numbers>
#include <tuple>
#include <vector>

#include "plate_flutter_reference.h"

namespace shellflow::testing::plate_reference {
namespace {

constexpr double pi = std::numbers::pi;

Plate panel(double b, Edge x_edges, Edge y_edges, int modes_x, int modes_y) {
  Plate p;
  p.b = b;
  p.x_edges = x_edges;
  p.y_edges = y_edges;
  p.modes_x = modes_x;
  p.modes_y = modes_y;
  return p;
}
Plate ss(double b, int mx, int my) { return panel(b, Edge::simply_supported, Edge::simply_supported, mx, my); }
Plate clamped(double b, int mx, int my) { return panel(b, Edge::clamped, Edge::clamped, mx, my); }

double rel(double x, double ref) { return std::abs(x - ref) / std::abs(ref); }

TEST(PlateFlutterReference, InVacuoFrequencies) {
  // Simply supported (Navier): omega a^2 sqrt(rho h / D) = pi^2 (m^2 + n^2 (a/b)^2), exact with sine modes.
  for (const double b : {0.5, 0.25}) {
    const Plate p = ss(b, 6, 6);
    const std::vector<double> f = natural_frequencies_hz(p);
    std::vector<double> exact;
    for (int m = 1; m <= 6; ++m)
      for (int n = 1; n <= 6; ++n) exact.push_back(pi * pi * (m * m + n * n * (p.a / b) * (p.a / b)));
    std::sort(exact.begin(), exact.end());
    std::printf("simply supported, a/b = %g:  mode  f (Hz)  omega a^2 sqrt(rho h/D)  Navier\n", p.a / b);
    for (int i = 0; i < 6; ++i) {
      std::printf("  %d  %10.4f  %10.5f  %10.5f\n", i + 1, f[i], frequency_parameter(p, f[i]), exact[i]);
      EXPECT_LT(rel(frequency_parameter(p, f[i]), exact[i]), 1e-10);
    }
  }
  EXPECT_NEAR(frequency_parameter(ss(0.5, 2, 2), natural_frequencies_hz(ss(0.5, 2, 2))[0]), 2 * pi * pi, 1e-9);
  // Clamped square with beam functions: Leissa's Table 4.23 (Ritz, 1969) and the converged values of Gorman.
  const double leissa[6] = {35.992, 73.413, 73.413, 108.27, 131.64, 132.24};
  const double gorman[6] = {35.985, 73.394, 73.394, 108.22, 131.58, 132.20};
  std::printf("clamped square:  mode  f (Hz)  parameter (6x6, 10x10 modes)  Leissa  Gorman\n");
  const std::vector<double> f6 = natural_frequencies_hz(clamped(0.5, 6, 6));
  const std::vector<double> f10 = natural_frequencies_hz(clamped(0.5, 10, 10));
  for (int i = 0; i < 6; ++i) {
    const double o6 = frequency_parameter(Plate{}, f6[i]), o10 = frequency_parameter(Plate{}, f10[i]);
    std::printf("  %d  %10.4f  %10.5f  %10.5f  %8.3f  %8.3f\n", i + 1, f10[i], o6, o10, leissa[i], gorman[i]);
    EXPECT_LT(rel(o10, gorman[i]), 1e-3);
    EXPECT_LT(rel(o6, o10), 1e-3);
  }
  EXPECT_LT(rel(frequency_parameter(Plate{}, f10[0]), 35.985), 1e-3);
}

TEST(PlateFlutterReference, ClampedBeamFunctionsStable) {
  // The cancellation-free form must keep phi(1) = phi'(1) = 0 and ∫ phi^2 = 1 for high modes (beta ~ 70).
  Eigen::VectorXd xi, w;
  detail::gauss_legendre(120, xi, w);
  for (const int m : {1, 2, 5, 10, 21}) {
    const double beta = detail::clamped_beta(m);
    double norm = 0.0;
    for (int i = 0; i < xi.size(); ++i) norm += w(i) * std::pow(detail::clamped_beam(beta, xi(i), 0), 2);
    EXPECT_NEAR(std::cos(beta) * std::cosh(beta), 1.0, 1e-9 * std::cosh(beta));
    EXPECT_NEAR(detail::clamped_beam(beta, 1.0, 0), 0.0, 1e-12);
    EXPECT_NEAR(detail::clamped_beam(beta, 1.0, 1), 0.0, 1e-12 * beta);
    EXPECT_NEAR(detail::clamped_beam(beta, 0.0, 1), 0.0, 1e-12 * beta);
    EXPECT_NEAR(norm, 1.0, 1e-12);
  }
  EXPECT_NEAR(detail::clamped_beta(1), 4.730040744862704, 1e-12);
  EXPECT_NEAR(detail::clamped_beta(2), 7.853204624095838, 1e-12);
}

TEST(PlateFlutterReference, MatrixProperties) {
  // M, K symmetric positive definite; A1 + A1^T = ∫ d(phi_i phi_j)/dx dA = boundary term = 0 (w = 0 on x = 0, a).
  for (const Plate& p0 : {ss(0.5, 6, 3), clamped(0.5, 6, 3), panel(0.25, Edge::clamped, Edge::simply_supported, 5, 4),
                          panel(0.5, Edge::simply_supported, Edge::clamped, 4, 5)}) {
    for (const double R : {std::numeric_limits<double>::infinity(), 0.5 * 0.5 / (5 * 1.35e-3)}) {
      Plate p = p0;
      p.R = R;
      const Matrices m = assemble(p);
      EXPECT_LT((m.M - m.M.transpose()).norm(), 1e-14 * m.M.norm());
      EXPECT_LT((m.K - m.K.transpose()).norm(), 1e-13 * m.K.norm());
      EXPECT_LT((m.A1 + m.A1.transpose()).norm(), 1e-10 * m.A1.norm());
      EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(m.M).eigenvalues().minCoeff(), 0.0);
      EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(m.K).eigenvalues().minCoeff(), 0.0);
      // Quadrature: twice the default number of points changes nothing (1e-10 of the matrix norms).
      Plate fine = p;
      fine.quad_points = 2 * (2 * std::max({p.modes_x, p.modes_y, std::isfinite(R) ? inplane_modes(p) : 0}) + 20);
      const Matrices mf = assemble(fine);
      EXPECT_LT((mf.K - m.K).norm(), 1e-10 * m.K.norm());
      EXPECT_LT((mf.A1 - m.A1).norm(), 1e-10 * m.A1.norm());
      EXPECT_LT((mf.M - m.M).norm(), 1e-10 * m.M.norm());
    }
  }
}

TEST(PlateFlutterReference, TwoModeClosedForm) {
  // Sine modes (1,1), (2,1), r = a/b: per (a b / 4), M = rho h I, K = (D pi^4 / a^4) diag(k1, k2),
  // k_m = (m^2 + r^2)^2, and (4 / (a b)) A1 = [[0, -8/(3a)], [8/(3a), 0]]. Non-dimensionally
  // Omega^2 = pi^4 (k1 + k2)/2 ± sqrt((pi^4 (k2 - k1)/2)^2 - (8 lambda/3)^2): coalescence at
  // lambda_cr = 3 pi^4 (k2 - k1) / 16 (45 pi^4 / 16 = 273.96 for the strip, r -> 0), Omega_cr^2 = pi^4 (k1 + k2)/2.
  std::printf("two modes:  a/b  lambda_cr  closed form  f_cr (Hz)  closed form\n");
  for (const double b : {500.0, 1.0, 0.5, 0.25}) {
    const Plate p = ss(b, 2, 1);
    const double r2 = (p.a / b) * (p.a / b), k1 = (1 + r2) * (1 + r2), k2 = (4 + r2) * (4 + r2);
    const double lambda = 3 * std::pow(pi, 4) * (k2 - k1) / 16;
    const double f = std::sqrt(std::pow(pi, 4) * (k1 + k2) / 2) / (2 * pi * p.a * p.a) *
                     std::sqrt(flexural_rigidity(p) / (p.rho * p.h));
    const Flutter r = critical_lambda(p);
    std::printf("  %6.3f  %12.6f  %12.6f  %9.4f  %9.4f\n", p.a / b, r.lambda_cr, lambda, r.frequency_hz, f);
    EXPECT_LT(rel(r.lambda_cr, lambda), 1e-6);
    EXPECT_LT(rel(r.frequency_hz, f), 1e-4);  // the root frequency varies as sqrt(lambda - lambda_cr) above lambda_cr
  }
  EXPECT_NEAR(critical_lambda(ss(1e6, 2, 1)).lambda_cr, 45 * std::pow(pi, 4) / 16, 1e-6 * 273.96);
}

/// Convergence table of lambda_cr over modes_x (rows) and modes_y (columns); returns [row][col].
std::vector<std::vector<Flutter>> table(const char* name, Plate p, const std::vector<int>& mx,
                                        const std::vector<int>& my) {
  std::printf("%s: lambda_cr (f_cr Hz), modes_x down, modes_y =", name);
  for (const int n : my) std::printf("  %22d", n);
  std::printf("\n");
  std::vector<std::vector<Flutter>> t;
  for (const int m : mx) {
    std::printf("  %2d", m);
    t.emplace_back();
    for (const int n : my) {
      p.modes_x = m;
      p.modes_y = n;
      t.back().push_back(critical_lambda(p));
      std::printf("  %11.4f (%8.4f)", t.back().back().lambda_cr, t.back().back().frequency_hz);
    }
    std::printf("\n");
  }
  return t;
}

TEST(PlateFlutterReference, SimplySupportedSquareFlutter) {
  const auto t = table("SS square", ss(0.5, 1, 1), {2, 4, 6, 8, 10, 12}, {1, 2, 3});
  const double converged = t.back().back().lambda_cr;
  EXPECT_LT(rel(t[4][2].lambda_cr, converged), 1e-3);               // last refinement (10 -> 12 modes)
  EXPECT_LT(rel(converged, 512.0), 0.01);                           // Dowell: lambda_cr ~ 512 for a/b = 1
  EXPECT_NEAR(t.back()[0].lambda_cr, converged, 1e-9 * converged);  // flat SS: n families decouple
}

TEST(PlateFlutterReference, ClampedSquareAndRectangleFlutter) {
  const auto c = table("clamped square", clamped(0.5, 1, 1), {4, 6, 8, 10, 12}, {1, 3, 5});
  EXPECT_LT(rel(c[3][2].lambda_cr, c[4][2].lambda_cr), 2e-3);
  EXPECT_LT(rel(c[4][1].lambda_cr, c[4][2].lambda_cr), 2e-3);
  // modes_y converges more slowly (beam functions in y, n = 1, 3, 5, ... couple): modes_x = 12, modes_y = 7, 9.
  ScanOptions coarse;
  coarse.lambda_step = 20.0;
  const Flutter c7 = critical_lambda(clamped(0.5, 12, 7), 0.0, coarse);
  const Flutter c9 = critical_lambda(clamped(0.5, 12, 9), 0.0, coarse);
  std::printf("  12 x 7: %.4f (%.4f Hz), 12 x 9: %.4f (%.4f Hz)\n", c7.lambda_cr, c7.frequency_hz, c9.lambda_cr,
              c9.frequency_hz);
  EXPECT_LT(rel(c7.lambda_cr, c9.lambda_cr), 5e-4);
  EXPECT_LT(rel(c[4][2].lambda_cr, c9.lambda_cr), 1e-3);
  const auto r = table("SS 2:1 (a = 2b)", ss(0.25, 1, 1), {4, 6, 8, 10, 12, 14}, {1, 2});
  EXPECT_LT(rel(r[4][0].lambda_cr, r[5][0].lambda_cr), 2e-3);
  // Wide-panel limit b = 1000 a (n = 1): Dowell's 2-D values, pinned 343.3 and clamped 636.6.
  const Flutter pinned = critical_lambda(ss(500.0, 12, 1));
  const Flutter clamped_strip = critical_lambda(panel(500.0, Edge::clamped, Edge::simply_supported, 12, 1));
  std::printf("2-D limit (b = 1000 a, 12 modes): pinned %.4f (Dowell 343.3), clamped %.4f (Dowell 636.6)\n",
              pinned.lambda_cr, clamped_strip.lambda_cr);
  EXPECT_LT(rel(pinned.lambda_cr, 343.3), 5e-4);
  EXPECT_LT(rel(clamped_strip.lambda_cr, 636.6), 5e-4);
}

TEST(PlateFlutterReference, CurvedPanel) {
  // a = b = 0.5 m, a^2 / (R h) = 5, axis along the flow; convergence in w modes and in-plane modes Nu.
  Plate p = ss(0.5, 8, 3);
  const Flutter flat = critical_lambda(ss(0.5, 12, 1));
  p.R = p.a * p.a / (5 * p.h);
  std::printf("curved SS panel, R = %.4f m:  modes_x modes_y Nu  lambda_cr  f_cr (Hz)  ratio to flat  f1 f2 f3 (Hz)\n",
              p.R);
  std::vector<Flutter> r;
  for (const auto& [mx, my, nu] :
       {std::tuple{6, 3, 12}, {8, 3, 16}, {10, 3, 16}, {12, 3, 16}, {12, 5, 16}, {12, 5, 20}, {12, 5, 24}}) {
    p.modes_x = mx;
    p.modes_y = my;
    p.inplane_modes = nu;
    const Matrices m = assemble(p);
    r.push_back(critical_lambda(p, m));
    const std::vector<double> f = natural_frequencies_hz(m);
    std::printf("  %2d %2d %2d  %12.5f  %9.4f  %.6f  %9.4f %9.4f %9.4f\n", mx, my, nu, r.back().lambda_cr,
                r.back().frequency_hz, r.back().lambda_cr / flat.lambda_cr, f[0], f[1], f[2]);
  }
  const double best = r.back().lambda_cr;
  EXPECT_LT(rel(r[3].lambda_cr, r[2].lambda_cr), 1e-3);  // modes_x 10 -> 12
  EXPECT_LT(rel(r[4].lambda_cr, r[3].lambda_cr), 1e-4);  // modes_y 3 -> 5
  EXPECT_LT(rel(r[5].lambda_cr, best), 1e-5);            // Nu 20 -> 24
  const std::vector<double> f = natural_frequencies_hz(p);
  std::printf("  first six frequencies (12 x 5 modes, Nu 24):");
  for (int i = 0; i < 6; ++i) std::printf(" %.4f", f[i]);
  std::printf("\n");
  // Curvature stiffens the fundamental (immovable edges: mean hoop strain w/R is not relieved).
  EXPECT_GT(f[0], 1.2 * natural_frequencies_hz(ss(0.5, 4, 4))[0]);
  // Flat limit through the condensation path: R = 1e7 m (a^2/(R h) = 1.9e-5).
  Plate nearly_flat = ss(0.5, 12, 1);
  nearly_flat.R = 1e7;
  const Flutter lim = critical_lambda(nearly_flat);
  std::printf("  R = 1e7 m: lambda_cr %.8f, flat %.8f\n", lim.lambda_cr, flat.lambda_cr);
  EXPECT_LT(rel(lim.lambda_cr, flat.lambda_cr), 1e-6);
}

TEST(PlateFlutterReference, DampedFlutter) {
  // Mass-proportional aerodynamic damping (A0 = M / (rho h)): each eigenvalue mu of M^-1 (K + qA A1) gives
  // s^2 + c s + mu = 0, c = qA g_D / (rho h), unstable iff (Im mu)^2 > c^2 Re mu. Bisect that criterion on the
  // generalized eigenvalues and compare with the state-space scan of critical_lambda.
  const Plate p = ss(0.5, 8, 1);
  const Matrices m = assemble(p);
  const double D = flexural_rigidity(p), a3 = p.a * p.a * p.a;
  const Flutter undamped = critical_lambda(p, m);
  std::printf("damped SS square (8 modes):  Mach  g_D (s)  lambda_cr state space  closed criterion  f_cr (Hz)\n");
  for (const double mach : {1.5, 2.0, 3.0, 5.0}) {
    const double U = 340.0 * mach, g_D = piston_theory(1.0, U, mach).g_D;
    const auto unstable = [&](double lambda) {
      const double qA = lambda * D / a3, c = qA * g_D / (p.rho * p.h);
      const Eigen::GeneralizedEigenSolver<Eigen::MatrixXd> ges(m.K + qA * m.A1, m.M, false);
      for (Eigen::Index i = 0; i < ges.eigenvalues().size(); ++i) {
        const std::complex<double> mu = ges.eigenvalues()(i);
        if (mu.imag() * mu.imag() > c * c * mu.real() * (1 + 1e-12)) return true;
      }
      return false;
    };
    double lo = undamped.lambda_cr, hi = 4 * undamped.lambda_cr;
    while (hi - lo > 1e-10 * hi) (unstable(0.5 * (lo + hi)) ? hi : lo) = 0.5 * (lo + hi);
    const Flutter d = critical_lambda(p, m, g_D);
    std::printf("  %4.1f  %.4e  %12.5f  %12.5f  %9.4f\n", mach, g_D, d.lambda_cr, 0.5 * (lo + hi), d.frequency_hz);
    EXPECT_LT(rel(d.lambda_cr, 0.5 * (lo + hi)), 1e-6);
    EXPECT_GT(d.lambda_cr, undamped.lambda_cr);
  }
  const Flutter tiny = critical_lambda(p, m, 1e-9);
  EXPECT_LT(rel(tiny.lambda_cr, undamped.lambda_cr), 1e-4);
  EXPECT_LT(rel(tiny.frequency_hz, undamped.frequency_hz), 1e-3);
}

}  // namespace
}  // namespace shellflow::testing::plate_reference
