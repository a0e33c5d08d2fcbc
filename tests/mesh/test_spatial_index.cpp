#include <gtest/gtest.h>

#include <random>

#include "mesh_test_util.h"
#include "shellflow/mesh/gmsh_io.h"
#include "shellflow/mesh/spatial_index.h"

using namespace shellflow;
using namespace shellflow::mesh;

namespace {
const std::filesystem::path data_dir = SHELLFLOW_TEST_DATA_DIR;

std::vector<Vec3> random_points(int n, unsigned seed, double lo = 0.0, double hi = 1.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  std::vector<Vec3> p(static_cast<std::size_t>(n));
  for (auto& x : p) x = Vec3(u(rng), u(rng), u(rng));
  return p;
}
}  // namespace

TEST(PointIndex, NearestAndRadiusMatchBruteForce) {
  const auto points = random_points(500, 1);
  const PointIndex index(points);
  for (const Vec3& q : random_points(200, 2, -0.2, 1.2)) {
    std::vector<std::pair<double, Index>> all;
    for (Index i = 0; i < static_cast<Index>(points.size()); ++i) all.emplace_back((points[i] - q).norm(), i);
    std::sort(all.begin(), all.end());
    const auto hit = index.nearest(q);
    EXPECT_EQ(hit.index, all[0].second);
    EXPECT_NEAR(hit.distance, all[0].first, 1e-15);
    const auto five = index.nearest(q, 5);
    ASSERT_EQ(five.size(), 5u);
    for (int k = 0; k < 5; ++k) EXPECT_EQ(five[k].index, all[k].second);
    const double radius = 0.15;
    const auto near = index.within(q, radius);
    const auto expected = std::count_if(all.begin(), all.end(), [&](auto& e) { return e.first < radius; });
    EXPECT_EQ(static_cast<long>(near.size()), expected);
  }
}

TEST(BoxTree, ContainingMatchesBruteForce) {
  std::vector<Box> boxes;
  for (const Vec3& c : random_points(300, 3)) {
    Box b;
    b.extend(c);
    b.pad(0.05);
    boxes.push_back(b);
  }
  const BoxTree tree(boxes);
  for (const Vec3& q : random_points(300, 4)) {
    auto got = tree.containing(q);
    std::sort(got.begin(), got.end());
    std::vector<Index> expected;
    for (Index i = 0; i < static_cast<Index>(boxes.size()); ++i)
      if (boxes[i].contains(q)) expected.push_back(i);
    EXPECT_EQ(got, expected);
  }
}

TEST(CellLocator, FindsEveryPointInsideTheCubeAndNoneOutside) {
  const Mesh mesh = generate_mesh(data_dir / "unit_cube.geo", with_order(1), "cube");
  const CellLocator locator(mesh);
  for (const Vec3& p : random_points(2000, 5)) {
    const auto loc = locator.locate(p);
    ASSERT_TRUE(loc.has_value()) << p.transpose();
    const auto v = mesh.cells.element(loc->cell);
    const Vec3 x0 = mesh.nodes[v[0]];
    const Vec3 x = x0 + loc->xi[0] * (mesh.nodes[v[1]] - x0) + loc->xi[1] * (mesh.nodes[v[2]] - x0) +
                   loc->xi[2] * (mesh.nodes[v[3]] - x0);
    EXPECT_LT((x - p).norm(), 1e-13);
    EXPECT_GE(loc->xi.minCoeff(), -1e-10);
    EXPECT_LE(loc->xi.sum(), 1.0 + 1e-10);
  }
  EXPECT_FALSE(locator.locate(Vec3(1.01, 0.5, 0.5)).has_value());
  EXPECT_FALSE(locator.locate(Vec3(0.5, -1e-6, 0.5)).has_value());
  // Nodes themselves (on faces shared by many cells) are found.
  for (const Vec3& node : mesh.nodes) EXPECT_TRUE(locator.locate(node).has_value());
}

TEST(ClosestPointOnTriangle, MatchesDenseSampling) {
  const Vec3 a(0, 0, 0), b(1, 0.2, 0), c(0.3, 0.9, 0.1);
  auto at = [&](double s, double t) { return Vec3(a + s * (b - a) + t * (c - a)); };
  for (const Vec3& p : random_points(100, 6, -1.0, 2.0)) {
    const Vec2 xi = closest_point_on_triangle(p, a, b, c);
    EXPECT_GE(xi.minCoeff(), -1e-14);
    EXPECT_LE(xi.sum(), 1.0 + 1e-14);
    const double d = (at(xi[0], xi[1]) - p).norm();
    double best = 1e300;
    const int n = 200;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) best = std::min(best, (at(double(i) / n, double(j) / n) - p).norm());
    EXPECT_LE(d, best + 1e-12);
    EXPECT_GE(d, best - 1e-2);  // sampling resolution
  }
}

TEST(SurfaceLocator, ClosestPointOnCubeBoundaryMatchesBruteForce) {
  const Mesh mesh = generate_mesh(data_dir / "unit_cube.geo", with_order(1), "cube");
  const auto& sides = mesh.group("sides");
  const SurfaceLocator locator(mesh.nodes, sides.elements);
  for (const Vec3& p : random_points(300, 7, -0.5, 1.5)) {
    const auto hit = locator.closest(p);
    double best = 1e300;
    for (Index e = 0; e < sides.elements.size(); ++e) {
      const auto v = sides.elements.element(e);
      const Vec3 &x0 = mesh.nodes[v[0]], &x1 = mesh.nodes[v[1]], &x2 = mesh.nodes[v[2]];
      const Vec2 xi = closest_point_on_triangle(p, x0, x1, x2);
      best = std::min(best, (x0 + xi[0] * (x1 - x0) + xi[1] * (x2 - x0) - p).norm());
    }
    EXPECT_NEAR(hit.distance, best, 1e-14);
    EXPECT_NEAR((hit.point - p).norm(), hit.distance, 1e-14);
    // The sides are the planes x = 0, x = 1, y = 0, y = 1 clipped to 0 <= z <= 1.
    const Vec3 q = p.cwiseMax(0.0).cwiseMin(1.0);
    const double to_planes = std::min({std::abs(q.x()), std::abs(1 - q.x()), std::abs(q.y()), std::abs(1 - q.y())});
    const bool inside_xy = p.x() >= 0 && p.x() <= 1 && p.y() >= 0 && p.y() <= 1;
    if (inside_xy && p.z() >= 0 && p.z() <= 1) {
      EXPECT_NEAR(hit.distance, to_planes, 1e-12);
    }
  }
}
