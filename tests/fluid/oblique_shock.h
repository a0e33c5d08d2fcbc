#pragma once
// Test oracle: the theta–beta–M relation of an attached oblique shock (weak solution) and
// the pressure ratio across it, for an ideal gas.
#include <cmath>
#include <numbers>

namespace shellflow::fluid::test_support {

struct ObliqueShock {
  double beta;            ///< shock angle (rad)
  double pressure_ratio;  ///< p2 / p1
};

/// Weak-shock solution for upstream Mach number `mach` and deflection `theta` (rad):
/// bisection of tan(theta) = 2 cot(beta) (M^2 sin^2 beta - 1) / (M^2 (gamma + cos 2 beta) + 2)
/// between the Mach angle and the angle of maximum deflection.
inline ObliqueShock oblique_shock(double mach, double theta, double gamma = 1.4) {
  auto deflection = [&](double beta) {
    const double m2s2 = mach * mach * std::sin(beta) * std::sin(beta);
    return std::atan(2.0 / std::tan(beta) * (m2s2 - 1.0) / (mach * mach * (gamma + std::cos(2.0 * beta)) + 2.0));
  };
  // Angle of maximum deflection by golden-section search.
  double lo = std::asin(1.0 / mach), hi = 0.5 * std::numbers::pi;
  for (int i = 0; i < 200; ++i) {
    const double a = lo + (hi - lo) / 3, b = hi - (hi - lo) / 3;
    (deflection(a) < deflection(b) ? lo : hi) = (deflection(a) < deflection(b) ? a : b);
  }
  double b_lo = std::asin(1.0 / mach), b_hi = 0.5 * (lo + hi);
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (b_lo + b_hi);
    (deflection(mid) < theta ? b_lo : b_hi) = mid;
  }
  const double beta = 0.5 * (b_lo + b_hi);
  const double m2s2 = mach * mach * std::sin(beta) * std::sin(beta);
  return {beta, 1.0 + 2.0 * gamma / (gamma + 1.0) * (m2s2 - 1.0)};
}

}  // namespace shellflow::fluid::test_support
