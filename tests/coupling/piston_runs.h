#pragma once
// Piston-theory flutter runs of a case, for the tests: the coupled time run with the growth
// fit of one shell probe, and the linear eigenvalue of the same discrete system
// (test_piston_flutter.cpp for the strip, test_plate_time_runs.cpp for the 3-D plates).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "shellflow/coupling/linear_flutter.h"
#include "shellflow/coupling/response.h"
#include "shellflow/io/case_meshes.h"
#include "shellflow/setup/coupled_setup.h"
#include "shellflow/shell/shell_queries.h"

namespace coupling_test {

struct Flutter {
  double growth_rate = 0.0;          ///< 1/s
  double frequency = 0.0;            ///< Hz
  std::vector<double> t, w;          ///< the probe's history, one value per step (and t = 0)
  double coupling_iterations = 0.0;  ///< mean per step
};

/// The case's coupled time run to its time.end: w (the y component) at the shell point
/// nearest `probe`, fitted over [t0, end].
inline Flutter time_run(const shellflow::io::Case& c, const shellflow::Vec3& probe_point, double t0) {
  using namespace shellflow;
  const io::CaseMeshes meshes = io::load_case_meshes(c, std::nullopt);
  setup::CoupledSystem s = setup::build_coupled_system(c, meshes);
  const shell::ShellPoint probe = shell::ShellLocator(*s.shell).closest(probe_point).point;
  std::vector<double> t{0.0}, w{0.0};
  const auto steps = static_cast<long>(std::llround(c.time->end / c.time->step));
  double iterations = 0.0;
  for (long i = 0; i < steps; ++i) {
    iterations += s.driver->step(c.time->step).coupling_iterations;
    t.push_back(s.solver->time());
    w.push_back(shell::interpolate_nodal(*s.shell, probe, s.solver->displacement()).y());
  }
  const coupling::ResponseFit fit = coupling::fit_response(t, w, t0, c.time->end);
  EXPECT_GT(fit.extrema, 10);
  return {fit.growth_rate, fit.frequency_hz, t, w, iterations / double(steps)};
}

/// The eigenvalue of largest real part of M q'' + D q' + (K + A) q = 0 on the first
/// `modes` in-vacuo modes of the supported shell (coupling::LinearFlutterSystem).
inline Flutter eigen_analysis(const shellflow::io::Case& c, int modes) {
  using namespace shellflow;
  const io::CaseMeshes meshes = io::load_case_meshes(c, std::nullopt);
  setup::CoupledSystem s = setup::build_coupled_system(c, meshes);
  const coupling::PistonTheory& theory = s.piston->theory();
  const coupling::LinearFlutterSystem linear(*s.shell, modes);
  const auto roots =
      linear.eigenvalues(coupling::PistonAerodynamics(linear, theory)
                             .at_coefficients(theory.stiffness_coefficient(), theory.damping_coefficient()));
  const auto best =
      *std::max_element(roots.begin(), roots.end(), [](const auto& a, const auto& b) { return a.real() < b.real(); });
  return {best.real(), std::abs(best.imag()) / (2 * std::numbers::pi), {}, {}, 0.0};
}

}  // namespace coupling_test
