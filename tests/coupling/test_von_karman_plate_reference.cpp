// Tests of the independent von Kármán plate flutter reference model (von_karman_plate_reference.h): the beam
// basis, the condensed membrane force, the static large deflection of the clamped immovable square, the linear
// growth rate against the Galerkin eigenvalue, the flutter boundary and the limit cycle with its convergence.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "von_karman_plate_reference.h"

namespace shellflow::testing::von_karman {
namespace {

constexpr double kXi = 0.7, kEta = 0.5;  // the probe (0.7 a, 0.5 b)

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

TEST(VonKarmanReference, BeamModesAreOrthonormalClampedEigenfunctions) {
  const auto [x, w] = gauss_legendre(96);
  EXPECT_NEAR(BeamMode(1).beta, 4.730040745, 1e-9);
  EXPECT_NEAR(BeamMode(2).beta, 7.853204624, 1e-9);
  for (int m = 1; m <= 12; ++m) {
    const BeamMode bm(m);
    for (const double xi : {0.0, 1.0}) {  // clamped ends: phi = phi' = 0
      EXPECT_NEAR(bm(xi)[0], 0.0, 1e-12);
      EXPECT_NEAR(bm(xi)[1] / bm.beta, 0.0, 1e-12);
    }
    for (int n = 1; n <= 12; ++n) {
      const BeamMode bn(n);
      double mm = 0.0, kk = 0.0;
      for (std::size_t i = 0; i < x.size(); ++i)
        mm += w[i] * bm(x[i])[0] * bn(x[i])[0], kk += w[i] * bm(x[i])[2] * bn(x[i])[2];
      EXPECT_NEAR(mm, m == n ? 1.0 : 0.0, 1e-11) << m << " " << n;  // int phi_m phi_n = delta
      EXPECT_NEAR(kk / std::pow(bm.beta, 4), m == n ? 1.0 : 0.0, 1e-11)
          << m << " " << n;  // int phi'' phi'' = beta^4 delta
    }
  }
}

TEST(VonKarmanReference, CondensedMembraneForceMatchesPointwisePipeline) {
  Params s;
  s.modes_x = 4, s.modes_y = 3, s.span_symmetric = false;  // all parities
  const Model model(s);
  Eigen::VectorXd q = s.h * Eigen::VectorXd::Random(model.size());
  const Eigen::VectorXd f = model.membrane_force(q), fd = model.membrane_force_direct(q);
  EXPECT_LT((f - fd).norm(), 1e-10 * f.norm());
  EXPECT_NEAR(q.dot(f), 4.0 * model.membrane_energy(q), 1e-10 * q.dot(f));  // quartic energy: q . dU/dq = 4 U
  EXPECT_GT(model.membrane_energy(q), 0.0);
  const Eigen::MatrixXd J = model.membrane_jacobian(q);
  const double e = 1e-6 * s.h;
  for (int i = 0; i < model.size(); ++i) {
    Eigen::VectorXd dq = Eigen::VectorXd::Zero(model.size());
    dq(i) = e;
    const Eigen::VectorXd fd_col = (model.membrane_force(q + dq) - model.membrane_force(q - dq)) / (2.0 * e);
    EXPECT_LT((J.col(i) - fd_col).norm(), 1e-7 * J.norm()) << i;
  }
  EXPECT_LT((J - J.transpose()).norm(), 1e-12 * J.norm());
}

// Test 1: central deflection of the clamped, in-plane immovable square (nu = 0.33) under uniform pressure p,
// against P = p a^4/(E h^4). Doubly symmetric modes (odd m, odd n <= modes_x).
TEST(VonKarmanReference, StaticLargeDeflectionOfClampedImmovableSquare) {
  const auto t0 = std::chrono::steady_clock::now();
  const Params base;
  const double p_unit = base.E * std::pow(base.h / base.a, 4);  // p for P = 1 [Pa]
  const std::vector<double> loads = {25.0, 50.0, 100.0, 200.0, 400.0};
  const std::vector<int> orders = {5, 7, 9};  // highest m = n
  std::vector<std::vector<double>> w(orders.size());
  std::vector<double> linear(orders.size());
  std::printf("clamped immovable square: w0/h vs P = p a^4/(E h^4); linear coefficient w0 D/(p a^4)\n");
  std::printf("  m,n <=   linear coef  ");
  for (double P : loads) std::printf("  P=%-6.0f", P);
  std::printf("\n");
  for (std::size_t k = 0; k < orders.size(); ++k) {
    Params s = base;
    s.modes_x = orders[k], s.modes_y = (orders[k] + 1) / 2, s.x_symmetric = true, s.inplane = 12;
    Params lin = s;
    lin.nonlinear = false;
    linear[k] = static_center_deflection(lin, 1.0, 1) * bending_stiffness(s) / std::pow(s.a, 4);
    std::printf("  %6d   %.8f   ", orders[k], linear[k]);
    for (double P : loads)
      w[k].push_back(static_center_deflection(s, P * p_unit) / s.h), std::printf("  %8.5f", w[k].back());
    std::printf("\n");
    // Small-load limit of the nonlinear solve = the linear solution.
    EXPECT_NEAR(
        static_center_deflection(s, 0.01 * p_unit, 1) * bending_stiffness(s) / (0.01 * p_unit * std::pow(s.a, 4)),
        linear[k], 1e-4 * linear[k]);
  }
  // Timoshenko: w0 = 0.00126 p a^4/D (more digits: 0.0012653).
  EXPECT_NEAR(linear.back(), 0.00126, 0.005 * 0.00126);
  EXPECT_NEAR(linear.back(), 0.0012653, 0.001 * 0.0012653);
  for (std::size_t i = 0; i < loads.size(); ++i) {
    const double change = std::abs(w.back()[i] / w[w.size() - 2][i] - 1.0);
    EXPECT_LT(change, 0.01) << "P = " << loads[i];
    EXPECT_LT(w.back()[i], linear.back() * 12.0 * (1.0 - base.nu * base.nu) * loads[i]);  // membrane stiffening
  }
  EXPECT_GT(w.back()[3], 1.0);  // the refinement check covers w0/h ~ 1-2
  EXPECT_LT(w.back()[3], 2.0);
  std::printf("  (%.2f s)\n", seconds_since(t0));
}

// Test 2: with nonlinear = false the time run's growth rate and frequency (fit of the cycle amplitudes over
// [0.1, 0.3] s at the probe, start from the 1e-3 cavity dip) equal the leading eigenvalue of the same system.
TEST(VonKarmanReference, LinearTimeRunMatchesGalerkinEigenvalue) {
  std::printf("  M     lambda   eig growth [1/s]  eig f [Hz]   run growth   run f [Hz]\n");
  for (const double mach : {3.5, 4.0}) {
    Params s;
    s.mach = mach, s.nonlinear = false;
    const Eigenvalue e = linear_eigenvalue(s);
    const Response r = fit_growth(simulate(s, 0.3, kXi, kEta), 0.1);
    std::printf("  %.1f  %7.1f   %12.4f  %12.4f  %12.4f %12.4f\n", mach, lambda(s), e.growth_rate, e.frequency_hz,
                r.growth_rate, r.frequency_hz);
    EXPECT_GT(r.cycles, 15);
    EXPECT_NEAR(r.growth_rate, e.growth_rate, 0.01 * e.growth_rate);
    EXPECT_NEAR(r.frequency_hz, e.frequency_hz, 0.01 * e.frequency_hz);
  }
}

// Test 3: flutter boundary of the linear system, undamped (coalescence) and with the piston-theory damping.
TEST(VonKarmanReference, LinearFlutterBoundary) {
  std::printf("  modes      M_cr(undamped) lambda_cr   M_cr(damped) lambda_cr  f_cr [Hz]\n");
  std::vector<double> lam_u, lam_d;
  for (const auto& [mx, my] : std::vector<std::pair<int, int>>{{4, 3}, {6, 2}, {6, 3}, {6, 4}, {8, 3}, {10, 3}}) {
    Params s;
    s.modes_x = mx, s.modes_y = my;
    Params u = s, d = s;
    u.mach = flutter_mach(s, false), d.mach = flutter_mach(s, true);
    const Eigenvalue e = linear_eigenvalue(d);
    std::printf("  %2d x %d    %10.5f   %9.3f   %10.5f  %9.3f  %8.3f\n", mx, my, u.mach, lambda(u), d.mach, lambda(d),
                e.frequency_hz);
    EXPECT_NEAR(e.growth_rate, 0.0, 1e-3);
    EXPECT_GT(d.mach, u.mach);  // aerodynamic damping delays flutter
    lam_u.push_back(lambda(u)), lam_d.push_back(lambda(d));
  }
  EXPECT_LT(std::abs(lam_u[5] / lam_u[4] - 1.0), 0.001);  // 8 -> 10 streamwise modes
  EXPECT_LT(std::abs(lam_u[3] / lam_u[2] - 1.0), 0.001);  // n <= 5 -> n <= 7
  EXPECT_LT(std::abs(lam_d[5] / lam_d[4] - 1.0), 0.001);
  EXPECT_NEAR(lam_u[5], 851.5, 1.0);  // lambda_cr of the clamped square, ~850
  EXPECT_NEAR(lam_d[5], 856.0, 1.0);
  Params s;
  for (const double mach : {3.5, 4.0}) {
    s.mach = mach;
    EXPECT_GT(linear_eigenvalue(s).growth_rate, 0.0);
  }
  s.mach = 2.8;
  EXPECT_LT(linear_eigenvalue(s).growth_rate, 0.0);
}

Response lco(Params s) {
  s.init_w = 0.1 * s.h;  // faster onset than the cavity dip; the limit cycle does not depend on it
  const Response r = lco_response(s, 3.0, kXi, kEta);
  EXPECT_TRUE(r.converged);
  return r;
}
void print_lco(const char* label, const Params& s, const Response& r) {
  std::printf("  %-16s  A/h = %.5f  max/h = %.5f  f = %8.3f Hz  (converged at t = %.3f s)\n", label,
              r.lco_amplitude / s.h, r.plate_max_amplitude / s.h, r.frequency_hz, r.time);
}

// Test 4a: the limit cycle at M = 4.0 (lambda = 1138 = 1.33 lambda_cr): convergence in modes, in-plane basis, dt.
TEST(VonKarmanReference, LimitCycleConvergesInModesAndTimeStep) {
  const auto t0 = std::chrono::steady_clock::now();
  Params base;
  base.mach = 4.0;
  std::printf("M = %.1f, lambda = %.1f, probe (%.1f a, %.1f b)\n", base.mach, lambda(base), kXi, kEta);
  auto run = [](const Params& s, const std::string& label) {
    const Response r = lco(s);
    print_lco(label.c_str(), s, r);
    return r.lco_amplitude;
  };
  std::vector<double> ax, ay, at;
  for (const int mx : {4, 6, 8, 10}) {
    Params s = base;
    s.modes_x = mx;
    ax.push_back(run(s, "modes " + std::to_string(mx) + " x 3"));
  }
  for (const int my : {1, 2, 3, 4}) {
    Params s = base;
    s.modes_y = my;
    ay.push_back(run(s, "modes 8 x " + std::to_string(my)));
  }
  EXPECT_LT(std::abs(ax[3] / ax[2] - 1.0), 0.03);  // 8 -> 10 streamwise modes
  EXPECT_LT(std::abs(ax[2] / ax[1] - 1.0), 0.03);  // 6 -> 8
  EXPECT_LT(std::abs(ay[3] / ay[2] - 1.0), 0.03);  // n <= 5 -> n <= 7
  Params s = base;
  s.inplane = 24;
  EXPECT_LT(std::abs(run(s, "inplane 24") / ax[2] - 1.0), 0.005);
  for (const double dt : {2e-4, 1e-4, 5e-5}) {
    s = base;
    s.dt = dt;
    at.push_back(run(s, "dt = " + std::to_string(dt)));
  }
  EXPECT_LT(std::abs(at[2] / at[1] - 1.0), 0.005);
  EXPECT_LT(std::abs(at[1] / at[0] - 1.0), 0.005);
  std::printf("  (%.2f s)\n", seconds_since(t0));
}

// Test 4b: the case itself (start from the 1e-3 cavity dip) at M = 3.5 and 4.0.
TEST(VonKarmanReference, LimitCycleFromCavityDip) {
  Params cr;
  cr.mach = flutter_mach(cr, true);
  for (const double mach : {3.5, 4.0}) {
    Params s;
    const Response r = lco_at_mach(mach, s);
    s.mach = mach;
    const Eigenvalue e = linear_eigenvalue(s);
    std::printf("M = %.1f  lambda = %.1f = %.3f lambda_cr  linear: growth %.3f 1/s, f %.3f Hz\n", mach, lambda(s),
                lambda(s) / lambda(cr), e.growth_rate, e.frequency_hz);
    print_lco("from dip", s, r);
    EXPECT_TRUE(r.converged);
    EXPECT_NEAR(r.lco_amplitude / lco(s).lco_amplitude, 1.0, 0.002);          // independent of the start
    EXPECT_NEAR(r.lco_amplitude / s.h, mach < 3.75 ? 0.7550 : 1.0322, 0.01);  // regression (8 x 3 modes)
  }
}

// The spanwise-symmetric restriction: with all n and an antisymmetric (1,2) perturbation the antisymmetric part
// dies out and the limit cycle is that of the symmetric model.
TEST(VonKarmanReference, SymmetricLimitCycleIsStableToAntisymmetricPerturbation) {
  Params s;
  s.mach = 4.0, s.modes_x = 6, s.modes_y = 4, s.span_symmetric = false, s.dip = 0.0, s.init_w = 0.1 * s.h;
  const Model model(s);
  Eigen::VectorXd q0 = model.initial_q();
  q0(1) = 0.5 * q0(0);  // mode (1,2)
  const Eigen::VectorXd probe = model.shape_at(kXi, kEta);
  CycleTracker c;
  double anti_early = 0.0, anti_late = 0.0;
  integrate(
      model, 1.0,
      [&](double t, const Eigen::VectorXd& q) {
        c.add(t, probe.dot(q));
        double anti = 0.0;  // antisymmetric (even n) content
        for (int i = 0; i < model.size(); ++i)
          if (model.modes()[i].second % 2 == 0) anti = std::max(anti, std::abs(q(i)));
        if (t < 0.1) anti_early = std::max(anti_early, anti);
        if (t > 0.9) anti_late = std::max(anti_late, anti);
        return true;
      },
      q0);
  Params sym = s;
  sym.span_symmetric = true, sym.modes_y = 2;
  const double a_sym = lco(sym).lco_amplitude;
  const double a_all = c.amplitudes.back();
  std::printf("  antisymmetric |q| max: t < 0.1 s %.3e m, t > 0.9 s %.3e m; A/h all n %.5f, symmetric %.5f\n",
              anti_early, anti_late, a_all / s.h, a_sym / s.h);
  EXPECT_LT(anti_late, 1e-3 * anti_early);
  EXPECT_NEAR(a_all / a_sym, 1.0, 0.002);
}

}  // namespace
}  // namespace shellflow::testing::von_karman
