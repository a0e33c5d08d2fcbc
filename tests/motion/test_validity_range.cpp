// The largest single-mode panel deflection A sin(pi s / L) that keeps every fluid element
// valid, upward and downward, per mesh mover (motion.md "Tests"). Prints the table.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <limits>

#include "motion_test_util.h"
#include "shellflow/mesh/quality.h"
#include "shellflow/motion/laplace_mover.h"

using namespace shellflow;
using namespace shellflow::motion;
using motion_test::fluid;

namespace {

struct Amplitude {
  double value = 0.0;
};

/// Movers are built on a motion whose amplitude is read from `amplitude` at each update.
class VariableAmplitude final : public BoundaryMotion {
 public:
  explicit VariableAmplitude(const Amplitude& a) : amplitude_(a) {}
  int register_points(std::span<const Vec3> X) override {
    sets_.emplace_back(X.begin(), X.end());
    return static_cast<int>(sets_.size()) - 1;
  }
  void evaluate(int handle, double, std::span<Vec3> u, std::span<Vec3> v) const override {
    auto shape = motion_test::panel_motion(TimeFunction::constant(amplitude_.value));
    const auto& X = sets_[static_cast<std::size_t>(handle)];
    for (std::size_t i = 0; i < X.size(); ++i) {
      u[i] = shape.deflection(X[i], 0.0) * Vec3::UnitY();
      v[i] = Vec3::Zero();
    }
  }

 private:
  const Amplitude& amplitude_;
  std::vector<std::vector<Vec3>> sets_;
};

struct Quality {
  Index inverted;
  double min_ratio;     ///< min over elements of q / q0 (local loss)
  double minima_ratio;  ///< min q / min q0 (the worst element against the initial worst)
};

Quality quality_at(FluidMeshMover& mover, Amplitude& amplitude, double a, const std::vector<double>& q0) {
  amplitude.value = a;
  std::vector<Vec3> x(fluid().nodes.size()), w(x.size());
  mover.update(0.0, x, w);
  const auto q = mesh::cell_qualities(fluid(), x);
  Quality result{0, std::numeric_limits<double>::infinity(), 0.0};
  for (std::size_t e = 0; e < q.size(); ++e) {
    if (q[e] <= 0) ++result.inverted;
    result.min_ratio = std::min(result.min_ratio, q[e] / q0[e]);
  }
  result.minima_ratio = *std::min_element(q.begin(), q.end()) / *std::min_element(q0.begin(), q0.end());
  return result;
}

/// Largest |A| (sign given) with no inverted element, by bisection to 1 mm.
double valid_limit(FluidMeshMover& mover, Amplitude& amplitude, double sign, const std::vector<double>& q0) {
  double lo = 0.0, hi = 0.5;
  while (hi - lo > 1e-3) {
    const double mid = 0.5 * (lo + hi);
    (quality_at(mover, amplitude, sign * mid, q0).inverted == 0 ? lo : hi) = mid;
  }
  return lo;
}

struct Row {
  double down, up;
  Quality at_down, at_up;  ///< at -0.03 and +0.03 m
};

/// Measures one mover (its motion reads `amplitude`) and prints its row of the table.
Row measure(FluidMeshMover& mover, Amplitude& amplitude, const std::vector<double>& q0, const char* label) {
  Row r{valid_limit(mover, amplitude, -1.0, q0), valid_limit(mover, amplitude, +1.0, q0),
        quality_at(mover, amplitude, -0.03, q0), quality_at(mover, amplitude, +0.03, q0)};
  std::printf("%-24s  %10.3f  %8.3f   %19.3f  %10.3f   %19.3f  %10.3f\n", label, -r.down, r.up, r.at_down.min_ratio,
              r.at_down.minima_ratio, r.at_up.min_ratio, r.at_up.minima_ratio);
  return r;
}

void print_header() {
  std::printf(
      "\nmin q/q0: smallest ratio over elements; minq/minq0: worst element against the "
      "initial worst\n");
  std::printf(
      "mover        e  weighting  A_down [m]  A_up [m]   at -0.03 m: min q/q0, minq/minq0"
      "   at +0.03 m: min q/q0, minq/minq0\n");
}

}  // namespace

TEST(ValidityRange, SpaceMeshKeepsThePanelSlabValidBeyondTwelveCentimetres) {
  const auto q0 = mesh::cell_qualities(fluid());
  const auto& shell = motion_test::shell();
  const auto shell_areas = lumped_node_areas(shell.nodes, shell.cells);
  print_header();
  for (double e : {2.0, 3.0, 4.0}) {
    for (auto weighting : {IdwWeighting::plain, IdwWeighting::area}) {
      Amplitude amplitude;
      VariableAmplitude motion(amplitude);
      SpaceMeshMover mover(fluid(), motion_test::space(), motion_test::panel_options(e, weighting), motion, shell.nodes,
                           shell_areas);
      const auto label =
          fmt::format("space_mesh   {:.0f}  {}", e, weighting == IdwWeighting::plain ? "plain" : "area ");
      const Row r = measure(mover, amplitude, q0, label.c_str());
      if (e == 4.0 && weighting == IdwWeighting::plain) {
        // The targets: valid to at least +-0.12 m, and the worst element keeps at
        // least 90 % of the initial worst quality at +-0.03 m.
        EXPECT_GE(r.down, 0.12);
        EXPECT_GE(r.up, 0.12);
        EXPECT_GE(r.at_down.minima_ratio, 0.9);
        EXPECT_GE(r.at_up.minima_ratio, 0.9);
      }
    }
  }
  {
    Amplitude amplitude;
    VariableAmplitude motion(amplitude);
    DirectIdwMover mover(fluid(), motion_test::panel_groups(), motion);
    const Row r = measure(mover, amplitude, q0, "direct_idw   4  plain");
    EXPECT_GT(r.down, 0.05);
    EXPECT_GT(r.up, 0.05);
  }
}

// The Laplacian-smoothing baseline (motion/laplace_mover.h) on the same motion.
TEST(ValidityRange, LaplacianSmoothingKeepsThePanelSlabValidBeyondFiveCentimetres) {
  const auto q0 = mesh::cell_qualities(fluid());
  Amplitude amplitude;
  VariableAmplitude motion(amplitude);
  LaplaceMover mover(fluid(), motion_test::panel_groups(), motion);
  print_header();
  const Row r = measure(mover, amplitude, q0, "laplace      -  -    ");
  EXPECT_GE(r.down, 0.05);
  EXPECT_GE(r.up, 0.05);
}
