#include <gtest/gtest.h>

#include <cmath>

#include "shellflow/mesh/quality.h"

using shellflow::Vec3;
using namespace shellflow::mesh;

namespace {
// Regular tetrahedron with unit edges, positively oriented.
const Vec3 a(0, 0, 0), b(1, 0, 0), c(0.5, std::sqrt(3.0) / 2, 0), d(0.5, std::sqrt(3.0) / 6, std::sqrt(2.0 / 3.0));
}  // namespace

TEST(Quality, RegularTetrahedronHasUnitMeanRatio) {
  EXPECT_NEAR(tet_signed_volume(a, b, c, d), 1.0 / (6.0 * std::sqrt(2.0)), 1e-15);
  EXPECT_NEAR(tet_mean_ratio(a, b, c, d), 1.0, 1e-14);
}

TEST(Quality, MeanRatioIsInvariantUnderScalingAndRigidMotion) {
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const Vec3 shift(3, -1, 2);
  auto map = [&](const Vec3& p) { return Vec3(2.5 * (rotation * p) + shift); };
  const Vec3 e(0.1, 0.2, 0.9);  // a non-regular tetrahedron (a, b, c, e)
  EXPECT_NEAR(tet_mean_ratio(map(a), map(b), map(c), map(e)), tet_mean_ratio(a, b, c, e), 1e-13);
  EXPECT_LT(tet_mean_ratio(a, b, c, e), 1.0);
}

TEST(Quality, InvertedTetrahedronHasNegativeQualityAndDegenerateZero) {
  EXPECT_NEAR(tet_mean_ratio(a, c, b, d), -1.0, 1e-14);
  EXPECT_LT(tet_signed_volume(a, c, b, d), 0.0);
  EXPECT_EQ(tet_mean_ratio(a, b, c, Vec3(0.3, 0.3, 0.0)), 0.0);
}

TEST(Quality, EquilateralTriangleHasUnitQuality) {
  EXPECT_NEAR(triangle_quality(a, b, c), 1.0, 1e-14);
  EXPECT_NEAR(triangle_quality(a, b, Vec3(0.5, 0.1, 0)), 4 * std::sqrt(3.0) * 0.05 / (0.26 * 2 + 1), 1e-14);
}

TEST(Quality, SummaryCountsInvertedCellsAndFindsTheWorst) {
  Mesh mesh;
  mesh.nodes = {a, b, c, d, Vec3(0.5, std::sqrt(3.0) / 6, -0.2)};
  mesh.cells.type = ElementType::tet4;
  mesh.cells.connectivity = {0, 1, 2, 3, 0, 1, 2, 4};  // second one inverted
  const auto s = summarize_quality(mesh);
  EXPECT_EQ(s.inverted, 1);
  EXPECT_EQ(s.worst_cell, 1);
  EXPECT_LT(s.min, 0.0);
  EXPECT_LT(s.min_volume, 0.0);
  const auto q = cell_qualities(mesh);
  ASSERT_EQ(q.size(), 2u);
  EXPECT_NEAR(q[0], 1.0, 1e-14);
  EXPECT_NEAR(s.mean, 0.5 * (q[0] + q[1]), 1e-15);
}
