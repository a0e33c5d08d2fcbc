#include <gtest/gtest.h>

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
  SpaceMeshMover mover(fluid(), motion_test::space(), motion_test::panel_options(), motion,
                       motion_test::shell().nodes);
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
