// Large-amplitude free vibration of the reference strip with Newmark (beta = 1/4,
// gamma = 1/2): the energy error stays bounded and drops as dt^2 (shell.md §13 item 9).
#include <cmath>
#include <cstdio>
#include <numbers>

#include <gtest/gtest.h>

#include "shellflow/shell/modal.h"
#include "shellflow/shell/newmark_solver.h"
#include "reference_strip.h"

namespace shellflow::shell {
namespace {

TEST(ReferenceStripVibrationSlow, LargeAmplitudeEnergyErrorIsBoundedAndSecondOrder) {
  const ShellModel model = reference_strip();
  const ModalResult modes = natural_frequencies(model, 1, Eigen::VectorXd::Zero(model.num_dofs()));
  const Eigen::VectorXd& phi = modes.modes[0];
  const double f1 = modes.frequencies[0];
  // Peak deflection of about 1.5 h: membrane stretching matters (nonlinear range).
  double w_max = 0.0;
  for (Index n = 0; n < model.num_nodes(); ++n) w_max = std::max(w_max, std::abs(phi(7 * n + 1)));
  const double amplitude = 2.0 * 1.35e-3 / w_max;
  double worst[2] = {0.0, 0.0};
  for (int level = 0; level < 2; ++level) {
    const int steps_per_period = 20 << level;
    NewmarkSolver solver(model);
    solver.set_initial_state(Eigen::VectorXd::Zero(model.num_dofs()), amplitude * 2.0 * std::numbers::pi * f1 * phi);
    const double E0 = solver.kinetic_energy() + solver.strain_energy();
    double peak_w = 0.0;
    for (int s = 0; s < 2 * steps_per_period; ++s) {  // two periods
      solver.advance(1.0 / (steps_per_period * f1));
      worst[level] = std::max(worst[level], std::abs((solver.kinetic_energy() + solver.strain_energy()) / E0 - 1.0));
      for (Index n = 0; n < model.num_nodes(); ++n)
        peak_w = std::max(peak_w, std::abs(solver.displacement()(7 * n + 1)));
    }
    std::printf("large amplitude (peak w = %.2f h), dt = T/%d, 2 periods: max |E/E0 - 1| = %.2e\n",
                peak_w / 1.35e-3, steps_per_period, worst[level]);
    EXPECT_GT(peak_w, 1.0 * 1.35e-3);
  }
  // The trapezoidal rule conserves energy only in the linear range; here the error is the
  // quadrature error of the work of the stiffening membrane force, O(dt^2).
  EXPECT_LT(worst[1], 2e-2);
  EXPECT_GT(worst[0] / worst[1], 3.0);  // second order in dt
}

}  // namespace
}  // namespace shellflow::shell
