// Free vibration of the reference panel strip (shell-references.md): L = 0.5 m,
// h = 1.35 mm, E = 77.28 GPa, nu = 0.33, rho = 2710 kg/m³, clamped–clamped, symmetry planes
// on the long edges (cylindrical bending): 31.401, 86.557, 169.687 Hz.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "reference_strip.h"
#include "shellflow/core/error.h"
#include "shellflow/mesh/gmsh_io.h"
#include "shellflow/shell/modal.h"
#include "shellflow/shell/newmark_solver.h"
#include "structured_shell_mesh.h"

namespace shellflow::shell {
namespace {

TEST(ReferenceStripVibration, FirstThreeFrequenciesMatchPlateStripTheory) {
  const ShellModel model = reference_strip();
  ASSERT_EQ(model.num_nodes(), 244);
  const ModalResult modes = natural_frequencies(model, 3, Eigen::VectorXd::Zero(model.num_dofs()));
  const double reference[3] = {31.401, 86.557, 169.687};
  for (int k = 0; k < 3; ++k) {
    const double f = modes.frequencies[static_cast<std::size_t>(k)];
    std::printf("mode %d: %.4f Hz (reference %.3f, error %+.3f %%)\n", k + 1, f, reference[k],
                100.0 * (f / reference[k] - 1.0));
    EXPECT_NEAR(f / reference[k], 1.0, 2e-3) << "mode " << k + 1;
  }
  std::printf("subspace iterations: %d\n", modes.iterations);
}

TEST(ReferenceStripVibration, MoreModesThanFreeDofsWithMassNamesTheCause) {
  const ShellModel model = reference_strip();
  try {
    (void)natural_frequencies(model, 5000, Eigen::VectorXd::Zero(model.num_dofs()));
    FAIL() << "5000 modes of a model with " << model.num_dofs() << " dofs";
  } catch (const SolverError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("5000 modes asked for"), std::string::npos) << what;
    EXPECT_NE(what.find("free degrees of freedom with mass"), std::string::npos) << what;
  }
}

/// The first roots beta_k L of the clamped-free beam, cos(beta L) cosh(beta L) = -1.
double cantilever_root(int k) {
  double b = (k - 0.5) * std::numbers::pi;  // Newton from the asymptote
  for (int it = 0; it < 50; ++it) {
    const double f = std::cos(b) * std::cosh(b) + 1.0;
    const double df = -std::sin(b) * std::cosh(b) + std::cos(b) * std::sinh(b);
    b -= f / df;
  }
  return b;
}

TEST(CantileverPlateVibration, ShockTubePlateMeetsTheClampedFreeBeamInPlaneStrain) {
  // The plate of the shock-tube experiment of Giordano et al. (2005; issue 37): steel, E 220 GPa, nu 0.3,
  // rho 7600 kg/m3, 50 mm long, 1 mm thick, clamped at its foot, free at its tip, symmetry
  // planes on the span faces (plane strain). Euler-Bernoulli with E' = E / (1 - nu^2):
  // f_k = (beta_k L)^2 / (2 pi L^2) sqrt(E' h^2 / (12 rho)): 364.44, 2283.9 Hz. Transverse
  // shear and rotary inertia lower mode k by about (1 + 2 (1 + nu) / kappa) (beta_k r)^2 / 2
  // with r = h / sqrt(12): 2.4e-4 for mode 1, 1.5e-3 for mode 2. Measured on 10 cubic elements:
  // 364.318 and 2278.663 Hz, -0.009 % and -0.078 % from the corrected beam (2026-12-07).
  const double L = 0.05, h = 1e-3, E = 220e9, nu = 0.3, rho = 7600.0;
  ShellSection section;
  section.thickness = h;
  section.material = {E, nu, rho};
  ShellModel model(testing::structured_shell_mesh(L, 0.005, 10, 1, [](double s, double t) { return Vec3(s, 0.0, t); }),
                   section);
  model.add_support(Support::clamped("left"));
  model.add_support(Support::symmetry_plane("bottom", 2));
  model.add_support(Support::symmetry_plane("top", 2));
  const ModalResult modes = natural_frequencies(model, 2, Eigen::VectorXd::Zero(model.num_dofs()));
  const double bending = std::sqrt(E / (1.0 - nu * nu) * h * h / (12.0 * rho));
  const double shear_factor = 1.0 + 2.0 * (1.0 + nu) / (5.0 / 6.0);
  for (int k = 1; k <= 2; ++k) {
    const double beta = cantilever_root(k) / L;
    const double beam = beta * beta * bending / (2.0 * std::numbers::pi);
    const double timoshenko = beam * (1.0 - 0.5 * shear_factor * beta * beta * h * h / 12.0);
    const double f = modes.frequencies[std::size_t(k - 1)];
    std::printf("mode %d: %.3f Hz; Euler-Bernoulli %.3f Hz (%+.3f %%), with shear and rotary inertia %.3f (%+.3f %%)\n",
                k, f, beam, 100.0 * (f / beam - 1.0), timoshenko, 100.0 * (f / timoshenko - 1.0));
    EXPECT_NEAR(f / timoshenko, 1.0, 1e-3) << "mode " << k;
  }
  EXPECT_NEAR(cantilever_root(1), 1.8751040687, 1e-9);
  EXPECT_NEAR(cantilever_root(2), 4.6940911330, 1e-9);
}

/// Times where q(t) crosses zero downwards/upwards, by linear interpolation between steps.
std::vector<double> zero_crossings(const std::vector<double>& t, const std::vector<double>& q) {
  std::vector<double> crossings;
  for (std::size_t i = 2; i < q.size(); ++i)  // q(0) = 0 is not a crossing
    if ((q[i - 1] > 0.0) != (q[i] > 0.0))
      crossings.push_back(t[i - 1] + (t[i] - t[i - 1]) * q[i - 1] / (q[i - 1] - q[i]));
  return crossings;
}

TEST(ReferenceStripVibration, NewmarkPeriodMatchesTheFirstFrequency) {
  const ShellModel model = reference_strip();
  const ModalResult modes = natural_frequencies(model, 1, Eigen::VectorXd::Zero(model.num_dofs()));
  const Eigen::VectorXd& phi = modes.modes[0];
  const double f1 = modes.frequencies[0];
  // Small amplitude (linear range): modal velocity such that the peak deflection is ~1e-3 h.
  double w_max = 0.0;  // transverse (y) component of the mode
  for (Index n = 0; n < model.num_nodes(); ++n) w_max = std::max(w_max, std::abs(phi(7 * n + 1)));
  const double scale = 1.35e-6 / w_max;
  NewmarkSolver solver(model);
  solver.set_initial_state(Eigen::VectorXd::Zero(model.num_dofs()), scale * 2.0 * std::numbers::pi * f1 * phi);
  const double dt = 1.0 / (100.0 * f1);
  const Eigen::VectorXd Mphi = solver.mass() * phi;
  std::vector<double> t{0.0}, q{0.0};
  const double E0 = solver.kinetic_energy();
  double worst_energy = 0.0;
  for (int s = 0; s < 56; ++s) {  // past the first return at T/2
    solver.advance(dt);
    t.push_back(solver.time());
    q.push_back(Mphi.dot(solver.displacement()));
    worst_energy = std::max(worst_energy, std::abs((solver.kinetic_energy() + solver.strain_energy()) / E0 - 1.0));
  }
  std::printf("linear range: max |E/E0 - 1| = %.2e over %zu steps\n", worst_energy, t.size() - 1);
  EXPECT_LT(worst_energy, 1e-6);  // trapezoidal Newmark conserves energy in the linear range
  const auto crossings = zero_crossings(t, q);
  ASSERT_GE(crossings.size(), 1u);
  const double period = 2.0 * crossings.front();  // q = A sin(omega t): first return at T/2
  const double f_newmark = 1.0 / period;
  // Newmark's period elongation at omega dt = 2 pi / 100 is (omega dt)^2 / 12 = 3.3e-4.
  std::printf("Newmark (dt = T/100): f1 = %.4f Hz, modal %.4f Hz, reference 31.401 Hz (error %+.3f %%)\n", f_newmark,
              f1, 100.0 * (f_newmark / 31.401 - 1.0));
  EXPECT_NEAR(f_newmark / f1, 1.0 - std::pow(2.0 * std::numbers::pi / 100.0, 2) / 12.0, 1e-4);
  EXPECT_NEAR(f_newmark / 31.401, 1.0, 2e-3);
}

/// Free vibration in mode k (0-based) at small amplitude, dt = T_k / steps_per_period, for
/// 1.1 periods. Returns the frequency from the mean spacing of the zero crossings of
/// the modal coordinate q = phi_k^T M u (its half period).
double time_integrated_frequency(const ShellModel& model, const ModalResult& modes, int k, int steps_per_period,
                                 TimeScheme scheme, double* worst_energy = nullptr) {
  const Eigen::VectorXd& phi = modes.modes[static_cast<std::size_t>(k)];
  const double f = modes.frequencies[static_cast<std::size_t>(k)];
  double w_max = 0.0;
  for (Index n = 0; n < model.num_nodes(); ++n) w_max = std::max(w_max, std::abs(phi(7 * n + 1)));
  NewmarkOptions options;
  options.scheme = scheme;
  NewmarkSolver solver(model, options);
  solver.set_initial_state(Eigen::VectorXd::Zero(model.num_dofs()), 1.35e-6 / w_max * 2.0 * std::numbers::pi * f * phi);
  const double dt = 1.0 / (steps_per_period * f);
  const Eigen::VectorXd Mphi = solver.mass() * phi;
  const double E0 = solver.kinetic_energy();
  std::vector<double> t{0.0}, q{0.0};
  double worst = 0.0;
  for (int s = 0; s < steps_per_period + steps_per_period / 10; ++s) {  // crossings at T/2 and T
    solver.advance(dt);
    t.push_back(solver.time());
    q.push_back(Mphi.dot(solver.displacement()));
    worst = std::max(worst, std::abs((solver.kinetic_energy() + solver.strain_energy()) / E0 - 1.0));
  }
  if (worst_energy) *worst_energy = worst;
  const auto crossings = zero_crossings(t, q);
  if (crossings.size() < 2) return 0.0;
  const double half_period = (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
  return 0.5 / half_period;
}

TEST(ReferenceStripVibration, TimeIntegratedFrequenciesOfModesTwoAndThree) {
  const ShellModel model = reference_strip();
  const ModalResult modes = natural_frequencies(model, 3, Eigen::VectorXd::Zero(model.num_dofs()));
  const double reference[3] = {31.401, 86.557, 169.687};
  // At dt = T_k/100 the trapezoidal rule lengthens the period by (omega dt)^2/12 = 3.3e-4
  // (and the midpoint rule, identical to it for linear problems, too): small against the
  // 0.2 % tolerance, and checked against its formula.
  const int steps_per_period = 100;
  const double elongation = std::pow(2.0 * std::numbers::pi / steps_per_period, 2) / 12.0;
  for (int k = 1; k < 3; ++k) {
    const double f_modal = modes.frequencies[static_cast<std::size_t>(k)];
    for (const TimeScheme scheme : {TimeScheme::newmark, TimeScheme::midpoint}) {
      double worst_energy = 0.0;
      const double f = time_integrated_frequency(model, modes, k, steps_per_period, scheme, &worst_energy);
      std::printf(
          "mode %d, %s (dt = T/%d): %.4f Hz, modal %.4f Hz, reference %.3f Hz (error %+.3f %%), "
          "max |E/E0 - 1| = %.1e\n",
          k + 1, scheme == TimeScheme::newmark ? "newmark" : "midpoint", steps_per_period, f, f_modal, reference[k],
          100.0 * (f / reference[k] - 1.0), worst_energy);
      EXPECT_NEAR(f / f_modal, 1.0 - elongation, 1e-4) << "mode " << k + 1;
      EXPECT_NEAR(f / reference[k], 1.0, 2e-3) << "mode " << k + 1;
      EXPECT_LT(worst_energy, 1e-6);  // both schemes conserve a quadratic energy
    }
  }
}

TEST(ReferenceStripVibration, ModifiedNewtonFollowsTheFullNewtonTrajectory) {
  // Large-amplitude free vibration (peak deflection ~2 h, stiffening membrane), 60 steps of
  // T1/100: modified Newton (kept iteration matrix) must converge to the same states as full
  // Newton (within the Newton tolerances) with far fewer factorisations.
  const ShellModel model = reference_strip();
  const ModalResult modes = natural_frequencies(model, 1, Eigen::VectorXd::Zero(model.num_dofs()));
  const Eigen::VectorXd& phi = modes.modes[0];
  double w_max = 0.0;
  for (Index n = 0; n < model.num_nodes(); ++n) w_max = std::max(w_max, std::abs(phi(7 * n + 1)));
  const Eigen::VectorXd v0 = (2.0 * 1.35e-3 / w_max) * 2.0 * std::numbers::pi * modes.frequencies[0] * phi;
  const double dt = 0.01 / modes.frequencies[0];
  for (const TimeScheme scheme : {TimeScheme::newmark, TimeScheme::midpoint}) {
    NewmarkOptions full_options, modified_options;
    full_options.scheme = modified_options.scheme = scheme;
    modified_options.newton.modified = true;
    NewmarkSolver full(model, full_options), modified(model, modified_options);
    full.set_initial_state(Eigen::VectorXd::Zero(model.num_dofs()), v0);
    modified.set_initial_state(Eigen::VectorXd::Zero(model.num_dofs()), v0);
    double worst = 0.0, peak = 0.0;
    int full_iterations = 0, modified_iterations = 0;
    for (int step = 0; step < 60; ++step) {
      full_iterations += full.advance(dt);
      modified_iterations += modified.advance(dt);
      peak = std::max(peak, full.displacement().cwiseAbs().maxCoeff());
      worst = std::max(worst, (modified.displacement() - full.displacement()).cwiseAbs().maxCoeff());
    }
    std::printf(
        "%s: full Newton %d iterations / %d factorisations, modified %d / %d; max |u_mod - u_full| / "
        "peak = %.2e\n",
        scheme == TimeScheme::newmark ? "Newmark" : "midpoint", full_iterations, full.matrix_factorizations(),
        modified_iterations, modified.matrix_factorizations(), worst / peak);
    EXPECT_GT(peak, 1.35e-3);
    EXPECT_LT(worst / peak, 1e-6);
    EXPECT_EQ(full.matrix_factorizations(), full_iterations);
    EXPECT_LT(modified.matrix_factorizations(), full.matrix_factorizations() / 3);
  }
}

TEST(ReferenceStripVibration, NodalMassProductEqualsTheSparseMassProduct) {
  // NodalMass relies on every 3x3 block of M being a multiple of the identity and on empty
  // `a` rows: then its product equals M v for any v.
  const ShellModel model = reference_strip();
  SparseMatrix M = model.make_matrix();
  model.assemble_mass(M);
  const NodalMass nodal(M);
  const Eigen::VectorXd v = Eigen::VectorXd::Random(model.num_dofs());
  const Eigen::VectorXd expected = M * v;
  const double error = (nodal * v - expected).norm() / expected.norm();
  std::printf("nodal mass product vs sparse M v: rel. difference %.2e\n", error);
  EXPECT_LT(error, 1e-14);
}

}  // namespace
}  // namespace shellflow::shell
