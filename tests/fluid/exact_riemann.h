#pragma once
// Test oracle: the exact solution of the 1-D Riemann problem for an ideal gas (Toro,
// "Riemann Solvers and Numerical Methods for Fluid Dynamics", ch. 4): Newton iteration for
// the star pressure, then sampling of the self-similar solution at x/t.
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace shellflow::fluid::test_support {

struct State1d {
  double rho, u, p;
};

class ExactRiemann {
 public:
  ExactRiemann(State1d left, State1d right, double gamma = 1.4) : l_(left), r_(right), g_(gamma) {
    cl_ = std::sqrt(g_ * l_.p / l_.rho);
    cr_ = std::sqrt(g_ * r_.p / r_.rho);
    solve_star();
  }
  double p_star() const { return p_star_; }
  double u_star() const { return u_star_; }
  double rho_star_left() const { return star_density(l_, cl_); }
  double rho_star_right() const { return star_density(r_, cr_); }
  /// Speed of the right wave when it is a shock.
  double right_shock_speed() const {
    return r_.u + cr_ * std::sqrt((g_ + 1) / (2 * g_) * p_star_ / r_.p + (g_ - 1) / (2 * g_));
  }
  double left_shock_speed() const {
    return l_.u - cl_ * std::sqrt((g_ + 1) / (2 * g_) * p_star_ / l_.p + (g_ - 1) / (2 * g_));
  }
  /// Solution at similarity coordinate s = (x - x0) / t.
  State1d sample(double s) const {
    if (s <= u_star_) return sample_side(l_, cl_, s, -1.0);
    return sample_side(r_, cr_, s, +1.0);
  }

 private:
  // Pressure function f_K(p) and its derivative (Toro 4.6–4.7).
  void f(const State1d& k, double c, double p, double& value, double& derivative) const {
    if (p > k.p) {
      const double a = 2 / ((g_ + 1) * k.rho), b = (g_ - 1) / (g_ + 1) * k.p;
      const double q = std::sqrt(a / (p + b));
      value = (p - k.p) * q;
      derivative = q * (1 - 0.5 * (p - k.p) / (b + p));
    } else {
      value = 2 * c / (g_ - 1) * (std::pow(p / k.p, (g_ - 1) / (2 * g_)) - 1);
      derivative = 1 / (k.rho * c) * std::pow(p / k.p, -(g_ + 1) / (2 * g_));
    }
  }
  void solve_star() {
    double p = std::max(1e-12, 0.5 * (l_.p + r_.p));
    for (int it = 0; it < 200; ++it) {
      double fl, dl, fr, dr;
      f(l_, cl_, p, fl, dl);
      f(r_, cr_, p, fr, dr);
      const double next = std::max(1e-14, p - (fl + fr + r_.u - l_.u) / (dl + dr));
      const bool done = std::abs(next - p) < 1e-15 * (next + p);
      p = next;
      if (done) break;
    }
    double fl, dl, fr, dr;
    f(l_, cl_, p, fl, dl);
    f(r_, cr_, p, fr, dr);
    p_star_ = p;
    u_star_ = 0.5 * (l_.u + r_.u) + 0.5 * (fr - fl);
  }
  double star_density(const State1d& k, double) const {
    const double ratio = p_star_ / k.p, gg = (g_ - 1) / (g_ + 1);
    if (p_star_ > k.p) return k.rho * (ratio + gg) / (gg * ratio + 1);
    return k.rho * std::pow(ratio, 1 / g_);
  }
  // side = -1 for the left wave, +1 for the right one (mirror formulas).
  State1d sample_side(const State1d& k, double c, double s, double side) const {
    const double rho_star = star_density(k, c);
    if (p_star_ > k.p) {  // shock
      const double speed = side < 0 ? left_shock_speed() : right_shock_speed();
      if (side * (s - speed) >= 0) return k;
      return {rho_star, u_star_, p_star_};
    }
    const double c_star = c * std::pow(p_star_ / k.p, (g_ - 1) / (2 * g_));
    const double head = k.u + side * c, tail = u_star_ + side * c_star;
    if (side * (s - head) >= 0) return k;
    if (side * (s - tail) <= 0) return {rho_star, u_star_, p_star_};
    // inside the fan
    const double u = 2 / (g_ + 1) * (-side * c + (g_ - 1) / 2 * k.u + s);
    const double cf = 2 / (g_ + 1) * (c - side * (g_ - 1) / 2 * (k.u - s));
    const double rho = k.rho * std::pow(cf / c, 2 / (g_ - 1));
    return {rho, u, k.p * std::pow(cf / c, 2 * g_ / (g_ - 1))};
  }

  State1d l_, r_;
  double g_, cl_ = 0, cr_ = 0, p_star_ = 0, u_star_ = 0;
};

}  // namespace shellflow::fluid::test_support
