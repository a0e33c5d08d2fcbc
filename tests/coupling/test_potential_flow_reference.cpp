// Tests of the 3-D linearised supersonic potential-flow reference (potential_flow_reference.h): the analytic mode
// transforms against quadrature, its 2-D limit against Ackeret and the quasi-steady first order in s (the coefficient
// g_D of plate_flutter_reference.h), its high-Mach limit against piston theory (error falling as 1/M^2), the wide
// plate against the 2-D matrix (error falling as 1/b^2), and the clamped square's flutter root at Mach 3.5.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <vector>

#include "potential_flow_reference.h"

namespace shellflow::testing::potential_reference {
namespace {

Plate clamped_plate(double b, int modes_x, int modes_y) {
  Plate p;
  p.b = b;
  p.x_edges = p.y_edges = Edge::clamped;
  p.modes_x = modes_x;
  p.modes_y = modes_y;
  return p;
}

std::vector<int> all_modes(const Plate& p) {
  std::vector<int> v(static_cast<std::size_t>(p.modes_x * p.modes_y));
  for (std::size_t k = 0; k < v.size(); ++k) v[k] = static_cast<int>(k);
  return v;
}

/// The modes symmetric about mid-span (n odd), as the half model of cases/panel_3d/clamped_square.yaml keeps.
std::vector<int> symmetric_modes(const Plate& p) {
  std::vector<int> v;
  for (int m = 0; m < p.modes_x; ++m)
    for (int n = 0; n < p.modes_y; n += 2) v.push_back(m * p.modes_y + n);
  return v;
}

Eigen::MatrixXd restrict(const Eigen::MatrixXd& X, const std::vector<int>& k) { return X(k, k); }

double rel(const Eigen::MatrixXcd& X, const Eigen::MatrixXcd& ref) { return (X - ref).norm() / ref.norm(); }

// The air of cases/panel_3d/clamped_square.yaml.
Flow air(double mach) { return flow_from(0.339, 28000.0, 1.4, mach); }

TEST(PotentialFlowReference, ModeTransformsMatchQuadrature) {
  Eigen::VectorXd xi, w;
  plate_reference::detail::gauss_legendre(240, xi, w);
  const double L = 0.5;
  for (const Edge edge : {Edge::clamped, Edge::simply_supported})
    for (const int m : {1, 2, 5}) {
      const detail::Mode1D mode(edge, m, L);
      const plate_reference::detail::Basis1D basis(edge, m, L, xi);
      const double beta = edge == Edge::clamped ? plate_reference::detail::clamped_beta(m) : m * std::numbers::pi;
      // kL = beta and -beta hit the removable singularity of the trigonometric terms.
      for (const double kL : {0.0, 3.0, beta, -beta, beta * (1 + 1e-9), 17.3, -41.0}) {
        cplx q = 0.0;
        for (int i = 0; i < xi.size(); ++i) q += w(i) * basis.f[0](i, m - 1) * std::exp(cplx(0.0, -kL * xi(i)));
        q *= L;
        EXPECT_LT(std::abs(mode.transform(kL / L) - q), 1e-12 * L) << "mode " << m << ", kL " << kL;
      }
      EXPECT_EQ(mode.parity(), m % 2 == 1 ? 1 : -1);
    }
}

TEST(PotentialFlowReference, TwoDimensionalLimitIsAckeretThenQuasiSteady) {
  // s -> 0: A(s) = rho U^2 / beta (A1 + g_D s A0) + O(s^2) per unit span (the strip's Mach 2.3).
  const Plate p = clamped_plate(1.0, 4, 1);
  const plate_reference::Matrices m = plate_reference::assemble(p);
  const Flow f = air(2.3);
  const auto pt = plate_reference::piston_theory(f.rho, f.U(), f.mach);
  const Aerodynamics aero(p, all_modes(p), f, {150.0, 1e-11});
  const double delta = 1e-2 * f.U() / p.a;
  const Eigen::MatrixXcd A1 = aero.matrix_2d(delta), A2 = aero.matrix_2d(2.0 * delta);
  const Eigen::MatrixXcd ackeret = (pt.qA * m.A1 / p.b).cast<cplx>();  // A1 of the Ritz model carries ∫Y^2 = b
  const Eigen::MatrixXcd first = (pt.qA * pt.g_D * m.A0 / p.b).cast<cplx>();
  const double e0 = rel(2.0 * A1 - A2, ackeret);                                  // O(delta^2)
  const double e1 = rel((4.0 * A1 - A2 - 3.0 * ackeret) / (2.0 * delta), first);  // O(delta^2)
  std::printf("2-D limit, M 2.3, s = %.1f, %.1f 1/s: Ackeret %.2e, first order in s %.2e\n", delta, 2 * delta, e0, e1);
  EXPECT_LT(e0, 2e-5);
  EXPECT_LT(e1, 2e-3);
}

TEST(PotentialFlowReference, HighMachTendsToPistonTheoryAsOneOverMachSquared) {
  const Plate p = clamped_plate(0.5, 3, 2);
  const plate_reference::Matrices m = plate_reference::assemble(p);
  const cplx s(50.0, 600.0);
  double e[2];
  int k = 0;
  for (const double mach : {8.0, 16.0}) {
    const Flow f = air(mach);
    const Aerodynamics aero(p, all_modes(p), f);
    const Eigen::MatrixXcd piston = f.rho * f.a * (f.U() * m.A1.cast<cplx>() + s * m.A0.cast<cplx>());
    e[k++] = rel(aero.matrix(s), piston);
  }
  std::printf("3-D against rho a (w_t + U w_x): M 8 %.3e, M 16 %.3e, ratio %.3f\n", e[0], e[1], e[0] / e[1]);
  EXPECT_LT(e[1], 1e-2);
  EXPECT_NEAR(e[0] / e[1], 4.0, 0.4);
}

TEST(PotentialFlowReference, WidePlateTendsToTwoDimensionsAsOneOverSpanSquared) {
  // The clamped spanwise shape's transform lives at ky ~ 1/b and P depends on ky^2: the 3-D correction is O(1/b^2).
  const cplx s(50.0, 600.0);
  const Flow f = air(2.3);
  const Eigen::MatrixXcd two_d = Aerodynamics(clamped_plate(1.0, 3, 1), {0, 1, 2}, f).matrix_2d(s);
  double e[2];
  int k = 0;
  for (const double b : {2.0, 8.0}) {
    const Plate p = clamped_plate(b, 3, 1);
    e[k++] = rel(Aerodynamics(p, all_modes(p), f).matrix(s) / b, two_d);  // per unit span (∫Y^2 dy = b)
  }
  std::printf("3-D / span against 2-D: b = 4a %.3e, b = 16a %.3e, ratio %.3f\n", e[0], e[1], e[0] / e[1]);
  EXPECT_LT(e[1], 1e-3);
  EXPECT_NEAR(e[0] / e[1], 16.0, 2.0);
}

TEST(PotentialFlowReference, ClampedSquareFlutterRootAtMach35) {
  // 4 x 3 clamped beam functions, the spanwise-symmetric ones (8 modes); bench/coupling/potential_flow_square
  // converges the modes (docs/coupling.md). Regression pins: this model's own values at this mode count.
  const Plate p = clamped_plate(0.5, 4, 3);
  const plate_reference::Matrices m = plate_reference::assemble(p);
  const std::vector<int> k = symmetric_modes(p);
  const Eigen::MatrixXd M = restrict(m.M, k), K = restrict(m.K, k);
  const Flow f = air(3.5);
  const auto pt = plate_reference::piston_theory(f.rho, f.U(), f.mach);
  const Eigen::VectorXcd r =
      quadratic_roots(M, (pt.qA * pt.g_D* restrict(m.A0, k)).cast<cplx>(), (K + pt.qA* restrict(m.A1, k)).cast<cplx>());
  Eigen::Index top = 0;
  r.real().maxCoeff(&top);
  const Aerodynamics aero(p, k, f);
  const auto A = [&](cplx s) { return aero.matrix(s); };
  const Root root = flutter_root(M, K, A, r(top));
  const double pi2 = 2.0 * std::numbers::pi;
  std::printf(
      "clamped square, M 3.5: piston theory s = %.4f + %.3f i (%.3f Hz), potential flow %.4f + %.3f i "
      "(%.3f Hz) in %d p-k steps\n",
      r(top).real(), std::abs(r(top).imag()), std::abs(r(top).imag()) / pi2, root.s.real(), std::abs(root.s.imag()),
      std::abs(root.s.imag()) / pi2, root.iterations);
  // The root satisfies det(s^2 M + K + A(s)) = 0: the smallest singular value against the largest.
  const Eigen::JacobiSVD<Eigen::MatrixXcd> svd(root.s * root.s * M + K + A(root.s));
  EXPECT_LT(svd.singularValues().tail(1)(0) / svd.singularValues()(0), 1e-9);
  EXPECT_NEAR(r(top).real(), 78.1260, 1e-3);
  EXPECT_NEAR(root.s.real(), 81.7252, 2e-3);
  EXPECT_NEAR(std::abs(root.s.imag()) / pi2, 95.792, 1e-3);
}

}  // namespace
}  // namespace shellflow::testing::potential_reference
