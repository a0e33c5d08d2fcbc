// The Hermite window of a shell step at arbitrary points of the shell.
#include <gtest/gtest.h>

#include <random>

#include "coupling_test_util.h"
#include "shellflow/coupling/shell_motion.h"
#include "shellflow/shell/shell_queries.h"

namespace shellflow::coupling {
namespace {

Eigen::VectorXd random_field(Index n, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1e-3, 1e-3);
  Eigen::VectorXd v(n);
  for (Index i = 0; i < n; ++i) v[i] = u(rng);
  return v;
}

/// The strip's shell model and a random window: states (u0, v0) and (u1, v1), displacements
/// of order 1e-3 m, velocities of order 0.1 m/s.
struct RandomWindow {
  shell::ShellModel model = coupling_test::panel_model(coupling_test::strip());
  std::mt19937 rng;
  Eigen::VectorXd u0, v0, u1, v1;
  explicit RandomWindow(unsigned seed) : rng(seed) {
    const Index nd = model.num_dofs();
    u0 = random_field(nd, rng);
    v0 = random_field(nd, rng) * 100.0;
    u1 = random_field(nd, rng);
    v1 = random_field(nd, rng) * 100.0;
  }
};

const std::vector<shell::ShellPoint> some_points = {{0, Vec2(0.2, 0.3)}, {7, Vec2(0.0, 0.0)}, {39, Vec2(0.5, 0.5)}};

TEST(ShellStepMotion, FollowsTheCubicHermiteOfTheStepExactly) {
  const RandomWindow r(7);
  const auto& [model, rng, u0, v0, u1, v1] = r;
  // The window as the driver sets it: its length is the difference of the stored end times,
  // so that t1 maps to tau = 1 exactly.
  const double t0 = 0.01, t1 = t0 + 1e-4, dt = t1 - t0;
  ShellStepMotion motion(model, 1e-6);
  const auto& points = some_points;
  const int handle = motion.register_shell_points(points);
  motion.set_window(t0, dt, u0, v0, u1, v1);
  std::vector<Vec3> d(points.size()), v(points.size());
  for (const double tau : {0.0, 0.25, 0.7, 1.0}) {
    motion.evaluate(handle, tau == 1.0 ? t1 : t0 + tau * dt, d, v);
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Vec3 x0 = shell::interpolate_nodal(model, points[i], u0),
                 x1 = shell::interpolate_nodal(model, points[i], u1);
      const Vec3 w0 = shell::interpolate_nodal(model, points[i], v0),
                 w1 = shell::interpolate_nodal(model, points[i], v1);
      EXPECT_LT((d[i] - shell::hermite_position(x0, w0, x1, w1, dt, tau)).norm(), 1e-15) << "tau " << tau;
      EXPECT_LT((v[i] - shell::hermite_velocity(x0, w0, x1, w1, dt, tau)).norm(), 1e-12) << "tau " << tau;
      if (tau == 0.0) {
        EXPECT_LT((d[i] - x0).norm(), 1e-16);
        EXPECT_LT((v[i] - w0).norm(), 1e-13);
      }
      if (tau == 1.0) {
        EXPECT_LT((d[i] - x1).norm(), 1e-16);
        EXPECT_LT((v[i] - w1).norm(), 1e-13);
      }
    }
  }
  // The velocity is the time derivative of the position (central difference).
  const double h = 1e-9;
  std::vector<Vec3> dp(points.size()), dm(points.size()), tmp(points.size());
  motion.evaluate(handle, t0 + 0.4 * dt + h, dp, tmp);
  motion.evaluate(handle, t0 + 0.4 * dt - h, dm, tmp);
  motion.evaluate(handle, t0 + 0.4 * dt, d, v);
  for (std::size_t i = 0; i < points.size(); ++i)
    EXPECT_LT((v[i] - (dp[i] - dm[i]) / (2 * h)).norm(), 1e-5 * v[i].norm() + 1e-9);
}

TEST(ShellStepMotion, TimeModesRecombineToTheWindowAndANewWindowHasANewId) {
  const RandomWindow r(9);
  const auto& [model, rng, u0, v0, u1, v1] = r;
  ShellStepMotion motion(model, 1e-6);
  const auto& points = some_points;
  const int handle = motion.register_shell_points(points);
  ASSERT_EQ(motion.num_time_modes(), 4);
  const std::uint64_t at_rest = motion.window_id();
  for (const bool window : {true, false}) {
    if (window)
      motion.set_window(0.01, 1e-4, u0, v0, u1, v1);
    else
      motion.set_state(0.02, u1, v1);  // a window of zero length
    EXPECT_NE(motion.window_id(), at_rest);
    std::vector<std::vector<Vec3>> f(4, std::vector<Vec3>(points.size()));
    for (int k = 0; k < 4; ++k) motion.evaluate_time_mode(handle, k, f[std::size_t(k)]);
    for (const double tau : {0.0, 0.3, 1.0}) {
      const double t = window ? 0.01 + tau * 1e-4 : 0.02;
      double c[4], dc[4];
      motion.time_coefficients(t, c, dc);
      std::vector<Vec3> d(points.size()), v(points.size());
      motion.evaluate(handle, t, d, v);
      for (std::size_t i = 0; i < points.size(); ++i) {
        Vec3 dm = Vec3::Zero(), vm = Vec3::Zero();
        for (std::size_t k = 0; k < 4; ++k) {
          dm += c[k] * f[k][i];
          vm += dc[k] * f[k][i];
        }
        EXPECT_LT((dm - d[i]).norm(), 1e-18) << "window " << window << " tau " << tau;
        EXPECT_LT((vm - v[i]).norm(), 1e-15) << "window " << window << " tau " << tau;
      }
    }
  }
}

TEST(ShellStepMotion, RefusesPointsOffTheShell) {
  const shell::ShellModel model = coupling_test::panel_model(coupling_test::strip());
  ShellStepMotion motion(model, 1e-6);
  const std::vector<Vec3> off = {Vec3(0.5, 1e-3, 0.01)};
  EXPECT_THROW(motion.register_points(off), InputError);
}

}  // namespace
}  // namespace shellflow::coupling
