#include <gtest/gtest.h>

#include <numbers>

#include "motion_test_util.h"
#include "shellflow/mesh/quality.h"

using namespace shellflow;
using namespace shellflow::motion;
using motion_test::at;
using motion_test::fluid;

TEST(MeshMovers, MeshVelocityIsTheTimeDerivativeOfThePositions) {
  auto motion = motion_test::panel_motion(TimeFunction::sine(0.02, 30.0));
  SpaceMeshMover space_mover(fluid(), motion_test::space(), motion_test::panel_options(), motion,
                             motion_test::shell().nodes);
  DirectIdwMover direct(fluid(), motion_test::panel_groups(), motion);
  for (FluidMeshMover* mover : std::vector<FluidMeshMover*>{&space_mover, &direct}) {
    const double t = 0.004, h = 1e-6;
    const auto [x, w] = at(*mover, t);
    const auto [xp, wp] = at(*mover, t + h);
    const auto [xm, wm] = at(*mover, t - h);
    double max_w = 0, max_error = 0;
    for (std::size_t p = 0; p < x.size(); ++p) {
      max_w = std::max(max_w, w[p].norm());
      max_error = std::max(max_error, ((xp[p] - xm[p]) / (2 * h) - w[p]).norm());
    }
    EXPECT_GT(max_w, 1.0) << mover->name();  // 2 pi 30 Hz x 0.02 m = 3.8 m/s at the panel
    EXPECT_LT(max_error, 1e-6 * max_w) << mover->name();
  }
}

TEST(MeshMovers, FluidInterfaceNodesFollowTheBoundaryMotionExactly) {
  auto motion = motion_test::panel_motion(TimeFunction::constant(0.03));
  SpaceMeshMover mover(fluid(), motion_test::space(), motion_test::panel_options(), motion, motion_test::shell().nodes);
  const auto [x, w] = at(mover, 0.0);
  for (Index n : fluid().group("panel").nodes) {
    const Vec3& X = fluid().nodes[static_cast<std::size_t>(n)];
    EXPECT_EQ(x[static_cast<std::size_t>(n)].y(), motion.deflection(X, 0.0));
    EXPECT_EQ(x[static_cast<std::size_t>(n)].x(), X.x());
  }
  EXPECT_EQ(mover.location_report().located + mover.location_report().projected, fluid().num_nodes());
}

TEST(MeshMovers, DirectIdwMovesNoNodeFurtherThanThePanelAndKeepsTheMeshValid) {
  auto motion = motion_test::panel_motion(TimeFunction::constant(0.05));
  DirectIdwMover mover(fluid(), motion_test::panel_groups(), motion);
  const auto [x, w] = at(mover, 0.0);
  for (std::size_t p = 0; p < x.size(); ++p) {
    ASSERT_LE((x[p] - fluid().nodes[p]).norm(), 0.05 * (1 + 1e-12));
  }
  EXPECT_EQ(mesh::summarize_quality(fluid(), x).inverted, 0);
}

namespace {

/// Two panel modes sin(m pi s / L) along +y (m = 1, 2) with cubic time coefficients
/// c_k(t) = a_k t + b_k t^3, as time modes (modes = true) or only through evaluate()
/// (modes = false: the mover's direct path). next_window() changes the coefficients and
/// the modes (m = 2, 3).
class ModalPanelMotion final : public BoundaryMotion {
 public:
  explicit ModalPanelMotion(bool modes) : modes_(modes) {}
  int register_points(std::span<const Vec3> x) override {
    sets_.emplace_back(x.begin(), x.end());
    return int(sets_.size()) - 1;
  }
  void evaluate(int handle, double t, std::span<Vec3> u, std::span<Vec3> v) const override {
    double c[2], dc[2];
    time_coefficients(t, c, dc);
    const auto& set = sets_[std::size_t(handle)];
    for (std::size_t i = 0; i < set.size(); ++i) {
      u[i] = c[0] * shape(0, set[i]) + c[1] * shape(1, set[i]);
      v[i] = dc[0] * shape(0, set[i]) + dc[1] * shape(1, set[i]);
    }
  }
  int num_time_modes() const override { return modes_ ? 2 : 0; }
  std::uint64_t window_id() const override { return window_; }
  void evaluate_time_mode(int handle, int k, std::span<Vec3> field) const override {
    const auto& set = sets_[std::size_t(handle)];
    for (std::size_t i = 0; i < set.size(); ++i) field[i] = shape(k, set[i]);
  }
  void time_coefficients(double t, std::span<double> c, std::span<double> dc) const override {
    for (int k = 0; k < 2; ++k) {
      const double a = a_[k], b = b_[k];
      c[std::size_t(k)] = a * t + b * t * t * t;
      dc[std::size_t(k)] = a + 3 * b * t * t;
    }
  }
  void next_window() {
    ++window_;
    a_[0] = -0.5, a_[1] = 3.0, b_[0] = 40.0, b_[1] = -7.0;
    first_wave_ = 2;
  }

 private:
  Vec3 shape(int k, const Vec3& X) const {
    const double s = X.x() - 0.25;
    if (s < 0.0 || s > 0.5) return Vec3::Zero();
    return Vec3(0.0, std::sin(double(k + first_wave_) * std::numbers::pi * s / 0.5), 0.0);
  }
  int first_wave_ = 1;
  bool modes_;
  std::uint64_t window_ = 1;
  double a_[2] = {2.0, -1.0}, b_[2] = {-30.0, 12.0};
  std::vector<std::vector<Vec3>> sets_;
};

}  // namespace

TEST(MeshMovers, SpaceMeshMovesTimeModesOncePerWindowAndMatchesTheDirectPath) {
  ModalPanelMotion with_modes(true), without_modes(false);
  SpaceMeshMover modal(fluid(), motion_test::space(), motion_test::panel_options(), with_modes,
                       motion_test::shell().nodes);
  SpaceMeshMover direct(fluid(), motion_test::space(), motion_test::panel_options(), without_modes,
                        motion_test::shell().nodes);
  for (int window = 0; window < 2; ++window) {
    if (window == 1) {
      with_modes.next_window();
      without_modes.next_window();
    }
    for (const double t : {0.0, 0.013, 0.02}) {
      const auto [x, w] = at(modal, t);
      const auto [xd, wd] = at(direct, t);
      double max_u = 0, max_w = 0, x_error = 0, w_error = 0;
      for (std::size_t p = 0; p < x.size(); ++p) {
        max_u = std::max(max_u, (xd[p] - fluid().nodes[p]).norm());
        max_w = std::max(max_w, wd[p].norm());
        x_error = std::max(x_error, (x[p] - xd[p]).norm());
        w_error = std::max(w_error, (w[p] - wd[p]).norm());
      }
      if (t > 0.0) {
        EXPECT_GT(max_u, 1e-3) << "window " << window << " t " << t;
      }
      EXPECT_GT(max_w, 1e-2);
      // Linear in the motion: the same up to rounding (a few ulps of the displacement).
      EXPECT_LE(x_error, 1e-14 * std::max(max_u, 1e-3)) << "window " << window << " t " << t;
      EXPECT_LE(w_error, 1e-14 * max_w) << "window " << window << " t " << t;
      // Positions only: the same positions, bit for bit.
      std::vector<Vec3> x_only(x.size());
      modal.update(t, x_only, {});
      for (std::size_t p = 0; p < x.size(); ++p) ASSERT_EQ(x_only[p], x[p]);
      // The space mesh's own nodes follow too (its frames, its Jacobian check).
      const auto su = modal.space_mesh().displacement(), sd = direct.space_mesh().displacement();
      for (std::size_t i = 0; i < su.size(); ++i) ASSERT_LE((su[i] - sd[i]).norm(), 1e-14 * std::max(max_u, 1e-3));
    }
  }
}
