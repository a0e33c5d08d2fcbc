// Conservation by the shell time integrators (shell.md §7, §13 item 9): a free-flying plate,
// no supports and no loads, spinning about a tilted axis while its membrane breathes. Linear
// momentum is constant for both schemes; angular momentum drifts as O(dt^2) with the
// trapezoidal Newmark rule and is conserved by the implicit midpoint rule.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "shellflow/shell/newmark_solver.h"
#include "structured_shell_mesh.h"

namespace shellflow::shell {
namespace {

constexpr double kLength = 1.0, kWidth = 0.5, kThickness = 0.05, kDensity = 1.0;
const Vec3 kCentre(0.5 * kLength, 0.5 * kWidth, 0.0);
const Vec3 kTranslation(0.3, -0.2, 0.1);  // m/s
const Vec3 kSpin(0.8, -0.5, 2.0);         // rad/s, not about a principal axis: the plate tumbles
constexpr double kStretchRate = 2.0;      // 1/s, in-plane radial velocity about the centre

ShellModel free_plate(double poisson = 0.3) {
  ShellSection section;
  section.thickness = kThickness;
  // Soft (membrane wave speed ~33 m/s): the breathing period ~0.06 s is resolved by the steps.
  section.material = {1.0e3, poisson, kDensity};
  return ShellModel(
      testing::structured_shell_mesh(kLength, kWidth, 2, 1, [](double s, double t) { return Vec3(s, t, 0.0); }),
      section);
}

/// Rigid translation + spin about the centre + in-plane stretch; directors turn with the spin.
Eigen::VectorXd initial_velocity(const ShellModel& model) {
  Eigen::VectorXd v = Eigen::VectorXd::Zero(model.num_dofs());
  for (Index n = 0; n < model.num_nodes(); ++n) {
    const Vec3 r = model.mesh().nodes[static_cast<std::size_t>(n)] - kCentre;
    v.segment<3>(dofs_per_node * n) = kTranslation + kSpin.cross(r) + kStretchRate * Vec3(r.x(), r.y(), 0.0);
    v.segment<3>(dofs_per_node * n + 3) = kSpin.cross(model.directors()[static_cast<std::size_t>(n)]);
  }
  return v;
}

struct Drift {
  double linear = 0.0;   ///< max_t |P(t) - P(0)| / |P(0)|
  double angular = 0.0;  ///< max_t |L(t) - L(0)| / |L(0)|
  double energy = 0.0;   ///< max_t |E(t)/E(0) - 1|, E = T + U
  double max_strain_energy = 0.0;
};

Drift run(const ShellModel& model, TimeScheme scheme, double dt, double t_end) {
  NewmarkOptions options;
  options.scheme = scheme;
  NewmarkSolver solver(model, options);
  solver.set_initial_state(Eigen::VectorXd::Zero(model.num_dofs()), initial_velocity(model));
  const Vec3 P0 = solver.linear_momentum(), L0 = solver.angular_momentum();
  const double E0 = solver.kinetic_energy();
  Drift drift;
  const auto steps = static_cast<int>(std::lround(t_end / dt));
  for (int s = 0; s < steps; ++s) {
    solver.advance(dt);
    drift.linear = std::max(drift.linear, (solver.linear_momentum() - P0).norm() / P0.norm());
    drift.angular = std::max(drift.angular, (solver.angular_momentum() - L0).norm() / L0.norm());
    const double U = solver.strain_energy();
    drift.energy = std::max(drift.energy, std::abs((solver.kinetic_energy() + U) / E0 - 1.0));
    drift.max_strain_energy = std::max(drift.max_strain_energy, U);
  }
  return drift;
}

TEST(FreeFlyingPlate, InitialMomentaMatchTheRigidBodyValues) {
  const ShellModel model = free_plate();
  NewmarkSolver solver(model);
  solver.set_initial_state(Eigen::VectorXd::Zero(model.num_dofs()), initial_velocity(model));
  // The stretch about the centre carries no momentum; the spin none about the centre.
  const double mass = kDensity * kLength * kWidth * kThickness;
  const Vec3 P = mass * kTranslation;
  const Eigen::Matrix3d J =
      mass / 12.0 *
      Eigen::Vector3d(kWidth * kWidth + kThickness * kThickness, kLength * kLength + kThickness * kThickness,
                      kLength * kLength + kWidth * kWidth)
          .asDiagonal();
  const Vec3 L = kCentre.cross(P) + J * kSpin;
  std::printf("P = (%.6e, %.6e, %.6e), L = (%.6e, %.6e, %.6e)\n", P.x(), P.y(), P.z(), L.x(), L.y(), L.z());
  EXPECT_LT((solver.linear_momentum() - P).norm(), 1e-13 * P.norm());
  EXPECT_LT((solver.angular_momentum() - L).norm(), 1e-13 * L.norm());
  // Translation, spin and stretch are M-orthogonal here (the plate is symmetric about its centre).
  const double T = 0.5 * mass * kTranslation.squaredNorm() + 0.5 * kSpin.dot(J * kSpin) +
                   0.5 * kStretchRate * kStretchRate * mass * (kLength * kLength + kWidth * kWidth) / 12.0;
  EXPECT_NEAR(solver.kinetic_energy() / T, 1.0, 1e-13);
}

TEST(FreeFlyingPlate, MomentaOfNewmarkAndMidpoint) {
  const ShellModel model = free_plate();
  const double stretch_energy = 0.5 * kStretchRate * kStretchRate * kDensity * kLength * kWidth * kThickness *
                                (kLength * kLength + kWidth * kWidth) / 12.0;
  const double t_end = 0.12;  // two breathing periods; the plate turns by 0.26 rad
  Drift newmark[2], midpoint[2];
  for (int level = 0; level < 2; ++level) {
    const double dt = 2e-3 / (1 << level);
    newmark[level] = run(model, TimeScheme::newmark, dt, t_end);
    midpoint[level] = run(model, TimeScheme::midpoint, dt, t_end);
    for (const auto& [name, d] : {std::pair{"newmark ", newmark[level]}, std::pair{"midpoint", midpoint[level]}})
      std::printf("%s dt = %.0e: max |dP|/|P| = %.2e, max |dL|/|L| = %.2e, max |E/E0 - 1| = %.2e, max U = %.3e J\n",
                  name, dt, d.linear, d.angular, d.energy, d.max_strain_energy);
  }
  // The membrane really works: most of the stretch's kinetic energy is stored at times.
  EXPECT_GT(newmark[0].max_strain_energy, 0.5 * stretch_energy);
  EXPECT_GT(midpoint[0].max_strain_energy, 0.5 * stretch_energy);
  for (int level = 0; level < 2; ++level) {
    // Linear momentum: Σ F_int = 0 over the x rows of every element (Σφ = 1) and M is constant.
    EXPECT_LT(newmark[level].linear, 1e-10);
    EXPECT_LT(midpoint[level].linear, 1e-10);
    // Angular momentum: exact for the midpoint rule (y_mid × F_int(y_mid) sums to zero).
    EXPECT_LT(midpoint[level].angular, 1e-11);
  }
  // Trapezoidal Newmark: O(dt^2), the drift drops by 4 when dt halves.
  EXPECT_GT(newmark[1].angular, 1e-5);
  EXPECT_NEAR(newmark[0].angular / newmark[1].angular, 4.0, 0.4);
}

/// Nodal positions (x rows) of the free plate at t_end with step dt.
Eigen::VectorXd positions_at(const ShellModel& model, TimeScheme scheme, double dt, double t_end) {
  NewmarkOptions options;
  options.scheme = scheme;
  NewmarkSolver solver(model, options);
  solver.set_initial_state(Eigen::VectorXd::Zero(model.num_dofs()), initial_velocity(model));
  const auto steps = static_cast<int>(std::lround(t_end / dt));
  for (int s = 0; s < steps; ++s) solver.advance(dt);
  Eigen::VectorXd x(3 * model.num_nodes());
  for (Index n = 0; n < model.num_nodes(); ++n) x.segment<3>(3 * n) = node_position_increment(solver.displacement(), n);
  return x;
}

TEST(FreeFlyingPlate, SecondOrderConvergenceUnderStepHalving) {
  // Positions at t = 4.8 ms with dt = 0.2, 0.1, 0.05 ms against dt = 0.0125 ms. The steps
  // must resolve the stiffest motion the initial state excites, the director modes (thickness
  // stretch through Poisson, transverse shear; omega ~ sqrt(12 E / (rho h^2)) = 2.2e3 rad/s):
  // omega dt <= 0.44 here. With dt = 4, 2, 1 ms (omega dt = 9 to 2) the observed orders are
  // 1.4 and 0.9, not because the schemes are worse but because those modes are unresolved.
  const ShellModel model = free_plate();
  const double t_end = 4.8e-3, dt0 = 2e-4;
  for (const TimeScheme scheme : {TimeScheme::newmark, TimeScheme::midpoint}) {
    const Eigen::VectorXd reference = positions_at(model, scheme, dt0 / 16, t_end);
    double error[3];
    for (int level = 0; level < 3; ++level)
      error[level] = (positions_at(model, scheme, dt0 / (1 << level), t_end) - reference).norm() / reference.norm();
    const double order[2] = {std::log2(error[0] / error[1]), std::log2(error[1] / error[2])};
    std::printf("%s: relative position error %.2e, %.2e, %.2e at dt = 0.2, 0.1, 0.05 ms: observed order %.3f, %.3f\n",
                scheme == TimeScheme::newmark ? "newmark " : "midpoint", error[0], error[1], error[2], order[0],
                order[1]);
    for (const double p : order) {
      EXPECT_GT(p, 1.8);
      EXPECT_LT(p, 2.2);
    }
  }
}

}  // namespace
}  // namespace shellflow::shell
