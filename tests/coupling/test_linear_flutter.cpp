// Linear flutter analysis (coupling/linear_flutter.h) against the literature and an
// independent model: Dowell's 2-D panel in piston theory with mu/M -> 0 (Dowell,
// "Aeroelasticity of plates and shells", 1975): lambda_cr = 636.6 clamped-clamped, 343.3
// pinned-pinned, and the two-mode closed form 45 pi^4 / 16 = 273.96 pinned-pinned.
// The independent reference is the Euler-Bernoulli beam w'''' + lambda w' + w_tt = 0
// (non-dimensional) by central finite differences, its coalescence bisected.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "flutter_strip.h"
#include "shellflow/core/error.h"
#include "shellflow/coupling/discrete_flutter.h"
#include "shellflow/coupling/gaf_identification.h"
#include "shellflow/coupling/linear_flutter.h"
#include "shellflow/coupling/modal_aerodynamics.h"
#include "shellflow/coupling/piston_theory.h"

namespace shellflow::coupling {
namespace {

constexpr double pi = std::numbers::pi;
using namespace test_strip;

/// lambda_cr and the non-dimensional coalescence frequency omega_bar = omega sqrt(rho h a^4 / D)
/// of the finite-difference beam with n intervals.
std::pair<double, double> beam_reference(int n, Edges edges) {
  const int m = n - 1;  // interior unknowns
  const double dx = 1.0 / n;
  const double ghost = edges == Edges::clamped ? 1.0 : -1.0;  // w_-1 = +-w_1
  Eigen::MatrixXd D4 = Eigen::MatrixXd::Zero(m, m), D1 = Eigen::MatrixXd::Zero(m, m);
  const double c4[5] = {1, -4, 6, -4, 1};
  for (int i = 0; i < m; ++i)
    for (int k = -2; k <= 2; ++k) {
      const int j = i + k;
      if (j >= 0 && j < m) D4(i, j) += c4[k + 2] / std::pow(dx, 4);
      if (j == -2) D4(i, 0) += ghost * c4[k + 2] / std::pow(dx, 4);         // node -1 mirrors node 1
      if (j == m + 1) D4(i, m - 1) += ghost * c4[k + 2] / std::pow(dx, 4);  // node n+1 mirrors n-1
    }
  for (int i = 0; i < m; ++i) {
    if (i + 1 < m) D1(i, i + 1) = 0.5 / dx;
    if (i > 0) D1(i, i - 1) = -0.5 / dx;
  }
  // omega_bar^2 are the eigenvalues of D4 + lambda D1; flutter when the lowest pair is complex.
  const auto lowest = [&](double lambda) {
    const Eigen::EigenSolver<Eigen::MatrixXd> es(D4 + lambda * D1, false);
    std::complex<double> best(1e300, 0.0);
    for (const auto& z : es.eigenvalues())
      if (z.real() < best.real()) best = z;
    return best;
  };
  double lo = 100.0, hi = 1000.0;
  for (int it = 0; it < 32; ++it) {
    const double mid = 0.5 * (lo + hi);
    const auto z = lowest(mid);
    (std::abs(z.imag()) > 1e-9 * std::abs(z) ? hi : lo) = mid;
  }
  return {hi, std::sqrt(lowest(hi).real())};
}

double frequency_hz(double omega_bar) {
  const double D = E * h * h * h / (12.0 * (1.0 - nu * nu));
  return omega_bar * std::sqrt(D / (rho_m * h * std::pow(a, 4))) / (2.0 * pi);
}

TEST(LinearFlutter, DowellsClampedAndPinnedPanelsWithoutAerodynamicDamping) {
  // The beam reference at two resolutions, extrapolated (second order in 1/n).
  const auto richardson = [](Edges e) {
    const auto fine = beam_reference(300, e), coarse = beam_reference(150, e);
    return std::pair{fine.first + (fine.first - coarse.first) / 3, fine.second + (fine.second - coarse.second) / 3};
  };
  const auto clamped_ref = richardson(Edges::clamped), pinned_ref = richardson(Edges::pinned);
  std::printf(
      "finite-difference beam (n = 150, 300, extrapolated): clamped lambda_cr %.3f, omega_bar %.4f = %.3f "
      "Hz; pinned lambda_cr %.3f, omega_bar %.4f\n",
      clamped_ref.first, clamped_ref.second, frequency_hz(clamped_ref.second), pinned_ref.first, pinned_ref.second);
  EXPECT_NEAR(clamped_ref.first, 636.6, 0.002 * 636.6);
  EXPECT_NEAR(pinned_ref.first, 343.3, 0.002 * 343.3);

  std::printf("%6s %14s %10s %14s %10s\n", "nx", "clamped", "f_cr [Hz]", "pinned", "f_cr [Hz]");
  double clamped = 0, pinned = 0, f_clamped = 0;
  for (const int nx : {5, 10, 20, 40}) {
    const shell::ShellModel mc = strip(nx, Edges::clamped), mp = strip(nx, Edges::pinned);
    const PistonTheory pc = piston(mc), pp = piston(mp);
    const LinearFlutterSystem sc(mc, 16), sp(mp, 16);
    const auto rc =
        sweep_flutter(sc, PistonAerodynamics(sc, pc), setting(false), FlutterParameter::lambda, 0.0, 1000.0, 21);
    const auto rp =
        sweep_flutter(sp, PistonAerodynamics(sp, pp), setting(false), FlutterParameter::lambda, 0.0, 1000.0, 21);
    ASSERT_TRUE(rc.critical && rp.critical);
    clamped = rc.critical->lambda;
    pinned = rp.critical->lambda;
    f_clamped = rc.critical->frequency_hz;
    std::printf("%6d %14.3f %10.3f %14.3f %10.3f\n", nx, clamped, f_clamped, pinned, rp.critical->frequency_hz);
  }
  EXPECT_NEAR(clamped, 636.6, 0.005 * 636.6);
  EXPECT_NEAR(pinned, 343.3, 0.005 * 343.3);
  EXPECT_NEAR(clamped, clamped_ref.first, 0.005 * clamped_ref.first);
  EXPECT_NEAR(f_clamped, frequency_hz(clamped_ref.second), 0.005 * frequency_hz(clamped_ref.second));
}

TEST(LinearFlutter, TwoModePinnedPanelMeetsTheClosedForm) {
  // Two sine modes: coalescence at lambda = 45 pi^4 / 16 and omega^2 = (omega_1^2 + omega_2^2) / 2
  // (the piston-theory coupling of the two modes is antisymmetric, A_11 = A_22 = 0).
  const shell::ShellModel model = strip(40, Edges::pinned);
  const PistonTheory p = piston(model);
  const LinearFlutterSystem two(model, 2);
  const auto r =
      sweep_flutter(two, PistonAerodynamics(two, p), setting(false), FlutterParameter::lambda, 0.0, 1000.0, 11);
  ASSERT_TRUE(r.critical);
  const auto& f = two.in_vacuo_frequencies();
  const double f_closed = std::sqrt(0.5 * (f[0] * f[0] + f[1] * f[1]));
  std::printf(
      "two modes: lambda_cr %.4f (closed form %.4f), f_cr %.4f Hz (closed form %.4f Hz), modes %.4f, "
      "%.4f Hz\n",
      r.critical->lambda, 45 * std::pow(pi, 4) / 16, r.critical->frequency_hz, f_closed, f[0], f[1]);
  EXPECT_NEAR(r.critical->lambda, 45 * std::pow(pi, 4) / 16, 0.005 * 273.96);
  EXPECT_NEAR(r.critical->frequency_hz, f_closed, 1e-4 * f_closed);
  // The beam's 1st and 2nd frequencies (plane strain): f_n = (n pi / a)^2 sqrt(D / (rho h)) / (2 pi).
  EXPECT_NEAR(f[0], frequency_hz(pi * pi), 2e-3 * f[0]);
  EXPECT_NEAR(f[1], frequency_hz(4 * pi * pi), 2e-3 * f[1]);
}

TEST(LinearFlutter, ModalBasisAgreesWithTheFullSystem) {
  // A coarse strip (small enough for the dense full system): the lowest roots above the
  // boundary from 24 modes against every dof. The full spectrum also holds roots near the
  // thickness-stretch frequencies (MHz) that piston theory destabilises; they are the mesh's,
  // not the panel's, and the modal basis leaves them out (docs/flutter.md).
  const shell::ShellModel model = strip(6, Edges::clamped);
  const PistonTheory p = piston(model);
  const LinearFlutterSystem modal(model, 24), full(model, 0);
  const PistonAerodynamics am(modal, p), af(full, p);
  for (const bool damping : {false, true}) {
    const FlowCondition flow = setting(damping).flow(FlutterParameter::lambda, 800.0);
    const auto rm = modal.eigenvalues(am.at(flow)), rf = full.eigenvalues(af.at(flow));
    ASSERT_GE(rf.size(), rm.size());
    const auto least =
        *std::max_element(rm.begin(), rm.end(), [](const auto& x, const auto& y) { return x.real() < y.real(); });
    std::printf(
        "lambda 800 (damping %d): least stable modal root %.6f%+.6fi; %zu dofs with mass, highest full "
        "root %.3g%+.3gi\n",
        damping, least.real(), least.imag(), std::size_t(full.size()), rf.back().real(), rf.back().imag());
    EXPECT_GT(least.real(), 0.0);
    // The lowest 8 modal roots each have a full-system root next to them (truncation: 24
    // modes of the coarse strip shift the frequencies by ~1e-4).
    for (std::size_t k = 0; k < 8; ++k) {
      const auto near = *std::min_element(rf.begin(), rf.end(), [&](const auto& x, const auto& y) {
        return std::abs(x - rm[k]) < std::abs(y - rm[k]);
      });
      EXPECT_NEAR(rm[k].real(), near.real(), 1e-3 * std::abs(near)) << "root " << k;
      EXPECT_NEAR(rm[k].imag(), near.imag(), 5e-4 * std::abs(near)) << "root " << k;
    }
    // The full system's boundary, counting its lowest 12 roots, equals the modal one. The full
    // sweep starts at 0.95 of the modal boundary, stable there, and bisects to 1e-5 (each dense
    // solve of the 680-wide state matrix costs about a second).
    const auto bm = sweep_flutter(modal, am, setting(damping), FlutterParameter::lambda, 0.0, 1000.0, 11);
    ASSERT_TRUE(bm.critical);
    const double lm = bm.critical->lambda;
    const auto bf =
        sweep_flutter(full, af, setting(damping), FlutterParameter::lambda, 0.95 * lm, 1.05 * lm, 3, 1e-5, 12);
    ASSERT_FALSE(bf.points.empty());
    for (const auto& root : bf.points.front().eigenvalues) EXPECT_LT(root.real(), 1e-8 * bf.points.front().scale);
    ASSERT_TRUE(bf.critical);
    EXPECT_NEAR(bm.critical->lambda, bf.critical->lambda, 1e-4 * bf.critical->lambda);
  }
}

TEST(LinearFlutter, DampingRaisesTheBoundaryAndMachAndLambdaSweepsAgree) {
  const shell::ShellModel model = strip(20, Edges::clamped);
  const PistonTheory p = piston(model);
  const LinearFlutterSystem s(model, 16);
  const PistonAerodynamics aero(s, p);
  const auto undamped = sweep_flutter(s, aero, setting(false), FlutterParameter::lambda, 0.0, 1000.0, 21);
  const auto damped = sweep_flutter(s, aero, setting(true), FlutterParameter::lambda, 0.0, 1000.0, 21);
  const auto mach = sweep_flutter(s, aero, setting(true), FlutterParameter::mach, 1.5, 4.0, 26);
  ASSERT_TRUE(undamped.critical && damped.critical && mach.critical);
  std::printf(
      "clamped, 20 elements: lambda_cr %.3f (no damping), %.3f (damping at Mach 2.3, mu/M %.4g), Mach "
      "sweep M_cr %.5f -> lambda %.3f\n",
      undamped.critical->lambda, damped.critical->lambda, setting(true).mass_ratio_over_mach(rho_m, h),
      mach.critical->mach, mach.critical->lambda);
  EXPECT_GT(damped.critical->lambda, undamped.critical->lambda);
  // At M_cr of the Mach sweep the lambda sweep's damping (rho fixed, U from lambda) differs
  // only through beta(M): the two boundaries agree when M_cr is the case's Mach; elsewhere
  // lambda(M_cr) must at least be a stable/unstable boundary of the Mach sweep's own system.
  const FlutterSetting st = setting(true);
  EXPECT_NEAR(st.mach_of_lambda(st.lambda_of_mach(mach.critical->mach)), mach.critical->mach, 1e-9);
  EXPECT_LT(s.max_growth_rate(aero.at(st.flow(FlutterParameter::mach, mach.critical->mach * (1 - 1e-6)))), 0.0);
  EXPECT_GT(s.max_growth_rate(aero.at(st.flow(FlutterParameter::mach, mach.critical->mach * (1 + 1e-6)))), 0.0);
}

/// Piston theory with one extra flow state that the forces do not see (C = 0): the roots are
/// piston theory's and the state's pole.
class PistonWithSilentState final : public ModalAerodynamics {
 public:
  PistonWithSilentState(const LinearFlutterSystem& system, const PistonTheory& p, double pole)
      : piston_(system, p), pole_(pole), n_(system.size()) {}
  AeroStateSpace at(const FlowCondition& flow) const override {
    AeroStateSpace s = piston_.at(flow);
    s.A = Eigen::MatrixXd::Constant(1, 1, pole_);
    s.B0 = Eigen::MatrixXd::Ones(1, n_);  // driven by the motion, heard by nobody
    s.B1 = Eigen::MatrixXd::Zero(1, n_);
    s.C = Eigen::MatrixXd::Zero(n_, 1);
    return s;
  }
  std::unique_ptr<ModalAerodynamics> truncated(int) const override { return nullptr; }
  std::string name() const override { return "piston theory with a silent state"; }

 private:
  PistonAerodynamics piston_;
  double pole_;
  Eigen::Index n_;
};

TEST(LinearFlutter, AFlowStateEntersWhereTheStateSpaceModelPutsIt) {
  // Two modes; one flow state x' = -a x + b q1 + e q1', force c x on mode 1: mode 2 keeps
  // s = i omega_2, mode 1 and the state solve (s^2 + omega_1^2)(s + a) - c (b + e s) = 0.
  const shell::ShellModel model = strip(20, Edges::pinned);
  const LinearFlutterSystem two(model, 2);
  const double w1 = 2 * pi * two.in_vacuo_frequencies()[0], w2 = 2 * pi * two.in_vacuo_frequencies()[1];
  const double ra = 50.0, b = -3e4, e = 5.0, c = 10.0;
  AeroStateSpace aero;
  aero.D0 = aero.D1 = Eigen::MatrixXd::Zero(2, 2);
  aero.A = Eigen::MatrixXd::Constant(1, 1, -ra);
  aero.B0 = Eigen::MatrixXd::Zero(1, 2);
  aero.B1 = Eigen::MatrixXd::Zero(1, 2);
  aero.C = Eigen::MatrixXd::Zero(2, 1);
  aero.B0(0, 0) = b;
  aero.B1(0, 0) = e;
  aero.C(0, 0) = c;
  const auto roots = two.eigenvalues(aero);
  const auto cubic = [&](std::complex<double> s) { return (s * s + w1 * w1) * (s + ra) - c * (b + e * s); };
  int on_mode_2 = 0, on_cubic = 0;
  for (const auto& s : roots) {
    EXPECT_GE(s.imag(), 0.0);
    if (std::abs(s - std::complex<double>(0.0, w2)) < 1e-9 * w2) {
      ++on_mode_2;
      continue;
    }
    // |cubic(s)| against the size of its terms at |s|.
    const double scale = (std::norm(s) + w1 * w1) * (std::abs(s) + ra) + c * (b + e * std::abs(s));
    EXPECT_LT(std::abs(cubic(s)), 1e-12 * scale) << s;
    ++on_cubic;
  }
  EXPECT_EQ(on_mode_2, 1);
  EXPECT_EQ(on_cubic, 2);  // a complex pair counted once and the real root
  // Here the lag feeds energy into mode 1: its pair grows (about 11.7 1/s at 95.4 rad/s, the real
  // root about -73.4 1/s with the beam's omega_1).
  EXPECT_GT(two.max_growth_rate(aero), 0.0);
}

TEST(LinearFlutter, ASilentFlowStateLeavesPistonTheorysRootsAndBoundary) {
  // The modal basis and the full system (which inverts the whole state matrix when the model
  // has states): piston theory's roots plus the state's pole, to 1e-6 (the unbalanced state
  // matrix, omega_max^2 beside 1, gives its highest roots to ~1e-7 whatever the model: two
  // solves differ by that), and on the modal basis the same boundary. The full system's comparison keeps to its lowest
  // 12 roots: its highest (the mesh's thickness-stretch modes, ~1.7e7 rad/s) are the inverse's smallest eigenvalues,
  // and two inversions give them to ~1e-3 only.
  const shell::ShellModel model = strip(6, Edges::clamped);
  const PistonTheory p = piston(model);
  for (const int modes : {12, 0}) {
    const LinearFlutterSystem sys(model, modes);
    const PistonAerodynamics plain(sys, p);
    const PistonWithSilentState silent(sys, p, -250.0);
    const FlowCondition flow = setting(true).flow(FlutterParameter::lambda, 800.0);
    auto r0 = sys.eigenvalues(plain.at(flow));
    const auto r1 = sys.eigenvalues(silent.at(flow));
    ASSERT_EQ(r1.size(), r0.size() + 1) << modes;
    EXPECT_EQ(std::count_if(r1.begin(), r1.end(), [](const auto& z) { return std::abs(z + 250.0) < 1e-6; }), 1);
    r0.resize(std::min<std::size_t>(r0.size(), 12));
    for (const auto& z : r0) {
      const auto near = *std::min_element(
          r1.begin(), r1.end(), [&](const auto& x, const auto& y) { return std::abs(x - z) < std::abs(y - z); });
      EXPECT_LT(std::abs(near - z), 1e-6 * std::abs(z)) << "modes " << modes << " root " << z;
    }
    if (modes == 0) continue;  // a sweep of the full system takes a minute
    const auto b0 = sweep_flutter(sys, plain, setting(true), FlutterParameter::lambda, 0.0, 1000.0, 11);
    const auto b1 = sweep_flutter(sys, silent, setting(true), FlutterParameter::lambda, 0.0, 1000.0, 11);
    ASSERT_TRUE(b0.critical && b1.critical);
    EXPECT_NEAR(b1.critical->lambda, b0.critical->lambda, 1e-8 * b0.critical->lambda);
  }
}

TEST(LinearFlutter, AModelOfTheWrongSizeIsRefused) {
  const shell::ShellModel model = strip(6, Edges::clamped);
  const LinearFlutterSystem sys(model, 4);
  AeroStateSpace aero;
  aero.D0 = aero.D1 = Eigen::MatrixXd::Zero(4, 4);
  aero.A = Eigen::MatrixXd::Zero(2, 2);
  aero.B0 = aero.B1 = Eigen::MatrixXd::Zero(2, 4);
  aero.C = Eigen::MatrixXd::Zero(4, 3);
  EXPECT_THROW(sys.eigenvalues(aero), SolverError);
  aero.C = Eigen::MatrixXd::Zero(4, 2);
  EXPECT_NO_THROW(sys.eigenvalues(aero));
  aero.D1 = Eigen::MatrixXd::Zero(3, 3);
  EXPECT_THROW(sys.eigenvalues(aero), SolverError);
}

// ---- the discrete-time path (discrete_flutter.h) ---------------------------------------------

/// A model without memory: D alone, at step dt.
DiscreteStateSpace feedthrough(const Eigen::MatrixXd& D, double dt) {
  FirModel fir;
  fir.dt = dt;
  fir.taps = {D};
  return fir.state_space();
}

TEST(DiscreteFlutter, WithoutAFlowEveryRootIsNewmarksUndampedFrequency) {
  // Newmark's average acceleration keeps |z| = 1 and turns omega into (2/dt) atan(omega dt/2).
  const LinearFlutterSystem sys(strip(20, Edges::clamped), 8);
  const double dt = 1e-4;
  const auto roots = discrete_eigenvalues(sys, feedthrough(Eigen::MatrixXd::Zero(8, 8), dt), 1.0);
  ASSERT_EQ(roots.size(), 8u);
  for (std::size_t k = 0; k < 8; ++k) {
    const double omega = 2 * pi * sys.in_vacuo_frequencies()[k];
    const double newmark = 2.0 / dt * std::atan(0.5 * omega * dt);
    EXPECT_NEAR(roots[k].imag(), newmark, 1e-12 * newmark) << "mode " << k + 1;
    EXPECT_NEAR(roots[k].real(), 0.0, 1e-12 * newmark) << "mode " << k + 1;
  }
}

TEST(DiscreteFlutter, AQuasiSteadyModelIsNewmarkOfTheAerodynamicStiffness) {
  // D = piston theory's stiffness part at lambda 800: the roots are Newmark's of K - D, i.e.
  // for every eigenvalue mu of K - D, z = (1 - h mu +- i dt sqrt(mu)) / (1 + h mu), h = dt^2/4;
  // they converge to the continuous roots at second order in dt.
  const shell::ShellModel model = strip(20, Edges::clamped);
  const LinearFlutterSystem sys(model, 8);
  const PistonAerodynamics aero(sys, piston(model));
  const FlowCondition flow = setting(false).flow(FlutterParameter::lambda, 800.0);
  const Eigen::MatrixXd D = aero.at_coefficients(flow.dynamic_pressure_over_beta, 0.0).D0;
  const auto continuous = sys.eigenvalues(aero.at_coefficients(flow.dynamic_pressure_over_beta, 0.0));
  const Eigen::EigenSolver<Eigen::MatrixXd> es(sys.stiffness() - D, false);
  double previous = 0.0;
  for (const double dt : {2e-4, 1e-4, 5e-5}) {
    const auto roots = discrete_eigenvalues(sys, feedthrough(D, dt), 1.0);
    ASSERT_EQ(roots.size(), 8u);
    const double h = 0.25 * dt * dt;
    for (const auto& root : roots) {
      double nearest = 1e300;
      for (const std::complex<double> mu : es.eigenvalues())
        for (const double sign : {1.0, -1.0}) {
          const std::complex<double> z =
              (1.0 - h * mu + sign * std::complex<double>(0, dt) * std::sqrt(mu)) / (1.0 + h * mu);
          nearest = std::min(nearest, std::abs(std::log(z) / dt - root));
        }
      EXPECT_LT(nearest, 1e-9 * std::abs(root)) << "dt " << dt << " root " << root;
    }
    // The lowest pair (s and -conj(s), one frequency) against the continuous system.
    double error = 0.0;
    for (std::size_t k = 0; k < 2; ++k) {
      double nearest = 1e300;
      for (const auto& root : roots) nearest = std::min(nearest, std::abs(root - continuous[k]));
      error += nearest;
    }
    std::printf("dt %.0e: lowest roots %.4f%+.4fi, %.4f%+.4fi; continuous %.4f%+.4fi; error %.3e\n", dt,
                roots[0].real(), roots[0].imag(), roots[1].real(), roots[1].imag(), continuous[0].real(),
                continuous[0].imag(), error);
    if (previous > 0.0) {
      EXPECT_NEAR(previous / error, 4.0, 0.2);
    }
    previous = error;
  }
}

TEST(DiscreteFlutter, TheStepMatrixIsOneNewmarkStepWithTheModelsMemory) {
  // An independent time loop: Newmark solved for q_{n+1} with f_{n+1} = s sum_j H_j q_{n+1-j}
  // (the FIR itself, zero history), against T^n [q0; v0; 0].
  const LinearFlutterSystem sys(strip(8, Edges::clamped), 4);
  const double dt = 1e-4, scale = 3e4;
  FirModel fir;
  fir.dt = dt;
  for (int j = 0; j < 3; ++j) fir.taps.push_back(Eigen::MatrixXd::Random(4, 4) * std::pow(0.5, j));
  const DiscreteStateSpace ss = fir.state_space();
  const Eigen::MatrixXd T = discrete_step_matrix(sys, ss, scale);
  ASSERT_EQ(T.rows(), 2 * 4 + 8);
  const Eigen::MatrixXd& K = sys.stiffness();
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(4, 4);
  std::vector<Eigen::VectorXd> q{Eigen::VectorXd::Random(4) * 1e-6};
  Eigen::VectorXd v = Eigen::VectorXd::Random(4) * 1e-3;
  const auto force = [&](std::size_t n) {  // f_n from q_n, q_{n-1}, q_{n-2}
    Eigen::VectorXd f = Eigen::VectorXd::Zero(4);
    for (std::size_t j = 0; j < fir.taps.size() && j <= n; ++j) f += scale * fir.taps[j] * q[n - j];
    return f;
  };
  Eigen::VectorXd acc = -K * q[0] + force(0);
  Eigen::VectorXd Y = Eigen::VectorXd::Zero(T.rows());
  Y.head(4) = q[0];
  Y.segment(4, 4) = v;
  const double h = 0.25 * dt * dt;
  for (std::size_t n = 0; n < 30; ++n) {
    Eigen::VectorXd memory = Eigen::VectorXd::Zero(4);  // the taps j >= 1 of f_{n+1}
    for (std::size_t j = 1; j < fir.taps.size() && j <= n + 1; ++j) memory += scale * fir.taps[j] * q[n + 1 - j];
    const Eigen::VectorXd next = (I + h * K - h * scale * fir.taps[0]).lu().solve(q[n] + dt * v + h * acc + h * memory);
    q.push_back(next);
    const Eigen::VectorXd acc_next = -K * next + force(n + 1);
    v += 0.5 * dt * (acc + acc_next);
    acc = acc_next;
    Y = T * Y;
    EXPECT_LT((Y.head(4) - next).norm(), 1e-10 * next.norm()) << "step " << n + 1;
    EXPECT_LT((Y.segment(4, 4) - v).norm(), 1e-10 * v.norm()) << "step " << n + 1;
  }
}

TEST(DiscreteFlutter, AModelOfTheWrongSizeIsRefused) {
  const LinearFlutterSystem sys(strip(8, Edges::clamped), 4);
  EXPECT_THROW((void)discrete_eigenvalues(sys, feedthrough(Eigen::MatrixXd::Zero(3, 3), 1e-4), 1.0), SolverError);
  EXPECT_THROW((void)discrete_eigenvalues(sys, feedthrough(Eigen::MatrixXd::Zero(4, 4), 0.0), 1.0), SolverError);
}

}  // namespace
}  // namespace shellflow::coupling
