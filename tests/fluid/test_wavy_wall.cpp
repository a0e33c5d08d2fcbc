// The flow's error per wavelength on the wavy wall against linear supersonic theory
// (tests/support/wavy_wall.h, docs/fluid.md "Accuracy per wavelength"): the wall pressure's
// amplitude and phase at 8 cells per lambda_x / M, the acceptance level of 1 % and 1
// degree, and the convergence with the mesh.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "support/wavy_wall.h"

using shellflow::support::run_wavy_wall;
using shellflow::support::WavyWallResult;
using shellflow::support::WavyWallSetup;

namespace {

WavyWallResult run(double mach, double cells, bool weak = true) {
  WavyWallSetup s;
  s.mach = mach;
  s.cells_per_wavelength = cells;
  s.options.weak_slip_walls = weak;
  const auto r = run_wavy_wall(s);
  std::printf(
      "M %.1f, %g cells, %s walls: amplitude %.5f, phase %.3f deg, loss %.4f and drift %.3f deg per wavelength\n", mach,
      cells, weak ? "weak" : "strong", r.amplitude_ratio, r.phase_deg, r.loss_per_wavelength, r.drift_per_wavelength);
  return r;
}

}  // namespace

TEST(WavyWall, WeakSlipWallsGiveTheWallPressureWithin1PercentAnd1DegreeAt8Cells) {
  // Measured: M 2.3 0.99745 / -0.22 deg; M 3.5 0.99537 / -0.27 deg (the strong projection:
  // 1.0405 / 0.29 deg and 1.0687 / 0.46 deg).
  for (const double mach : {2.3, 3.5}) {
    const auto weak = run(mach, 8);
    EXPECT_NEAR(weak.amplitude_ratio, 1.0, 0.01) << "M " << mach;
    EXPECT_NEAR(weak.phase_deg, 0.0, 1.0) << "M " << mach;
    // Along the Mach lines the wave loses under 1 % per wavelength travelled.
    EXPECT_LT(std::abs(weak.loss_per_wavelength), 0.01) << "M " << mach;
  }
}

TEST(WavyWall, TheStrongProjectionIsFiveTimesFartherOffThanTheWeakWall) {
  const auto weak = run(3.5, 8), strong = run(3.5, 8, false);
  EXPECT_GT(strong.amplitude_ratio - 1.0, 5.0 * std::abs(weak.amplitude_ratio - 1.0));
}

TEST(WavyWall, TheWeakWallsAmplitudeErrorFallsAtLeastAtSecondOrder) {
  // Measured: 2.55e-3 at 8 cells, 2.47e-4 at 16 (order 3.4); phase 0.216 -> 0.011 deg.
  const auto coarse = run(2.3, 8), fine = run(2.3, 16);
  const double order = std::log2(std::abs(coarse.amplitude_ratio - 1.0) / std::abs(fine.amplitude_ratio - 1.0));
  EXPECT_GE(order, 2.0);
  EXPECT_LT(std::abs(fine.phase_deg), 0.25 * std::abs(coarse.phase_deg));
}

TEST(WavyWall, ATravellingWaveOnADeflectingMeshMeetsTheTheoryInTheWavesFrame) {
  // y_w = A sin(k (x - V t)), V = c / 2, at M 3.5: the wall moves the mesh (ALE terms, moving
  // normals) and the pressure is that of the steady wall at M_r = 3 in the wave's frame.
  // Measured: 0.99723, 0.025 deg.
  WavyWallSetup s;
  s.mach = 3.5;
  s.wave_speed = 0.5;
  s.moving_mesh = true;
  const auto r = run_wavy_wall(s);
  EXPECT_NEAR(r.amplitude_ratio, 1.0, 0.01);
  EXPECT_NEAR(r.phase_deg, 0.0, 1.0);
}

TEST(WavyWall, UnstructuredTetrahedraAt8CellsMissThe1PercentBy03) {
  // Gmsh tetrahedra (3 cells across the span) at M 2.3: 0.98684 / -0.52 deg measured, the
  // issue's 1 % missed (docs/fluid.md); at 16 cells within it.
  WavyWallSetup s;
  s.unstructured = true;
  const auto r = run_wavy_wall(s);
  EXPECT_NEAR(r.amplitude_ratio, 1.0, 0.015);
  EXPECT_NEAR(r.phase_deg, 0.0, 1.0);
}
