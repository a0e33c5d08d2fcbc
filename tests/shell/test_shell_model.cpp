// The assembled model: mass totals, tangent against finite differences of the assembled
// internal force (parallel colouring), rigid motion of a whole mesh, bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "reference_strip.h"
#include "shellflow/core/error.h"

namespace shellflow::shell {
namespace {

TEST(ShellModel, AssembledMassTotalIsDensityThicknessArea) {
  const ShellModel model = reference_strip();
  SparseMatrix M = model.make_matrix();
  model.assemble_mass(M);
  Eigen::VectorXd ones_x = Eigen::VectorXd::Zero(model.num_dofs());
  for (Index n = 0; n < model.num_nodes(); ++n) ones_x(7 * n) = 1.0;
  const double mass = ones_x.dot(M * ones_x);
  EXPECT_NEAR(mass / (2710.0 * 1.35e-3 * 0.5 * 0.025), 1.0, 1e-13);
}

TEST(ShellModel, AssembledTangentIsTheDirectionalDerivativeOfTheInternalForce) {
  const ShellModel model = reference_strip();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  Eigen::VectorXd u(model.num_dofs()), direction(model.num_dofs());
  for (Eigen::Index i = 0; i < u.size(); ++i) {
    const double scale = i % 7 < 3 ? 1e-3 : 1e-2;  // a few thicknesses of deflection
    u(i) = scale * d(rng);
    direction(i) = scale * d(rng);
  }
  SparseMatrix K = model.make_matrix();
  Eigen::VectorXd f, fp, fm;
  ASSERT_TRUE(model.assemble(u, f, &K));
  const double step = 1e-6;
  model.assemble(u + step * direction, fp, nullptr);
  model.assemble(u - step * direction, fm, nullptr);
  const Eigen::VectorXd fd = (fp - fm) / (2 * step);
  const Eigen::VectorXd Kd = K * direction;
  EXPECT_LT((Kd - fd).norm() / Kd.norm(), 1e-6);
  EXPECT_LT((Eigen::MatrixXd(K) - Eigen::MatrixXd(K).transpose()).norm() / Eigen::MatrixXd(K).norm(), 1e-14);
}

TEST(ShellModel, RigidRotationOfTheWholeMeshGivesNoForce) {
  const ShellModel model = reference_strip();
  const Mat3 R = Eigen::AngleAxisd(2.0, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  Eigen::VectorXd u = Eigen::VectorXd::Zero(model.num_dofs());
  for (Index n = 0; n < model.num_nodes(); ++n) {
    const Vec3& X = model.mesh().nodes[static_cast<std::size_t>(n)];
    const Vec3& V = model.directors()[static_cast<std::size_t>(n)];
    u.segment<3>(7 * n) = R * X + Vec3(0.1, 0.2, 0.3) - X;
    u.segment<3>(7 * n + 3) = R * V - V;
  }
  Eigen::VectorXd f;
  ASSERT_TRUE(model.assemble(u, f, nullptr));
  // Force scale E h ~ 1e8 N/m times an element size ~ 0.01 m.
  EXPECT_LT(f.cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT(model.strain_energy(u), 1e-14);
}

TEST(ShellModel, BadInputStopsWithAMessage) {
  const ShellModel model = reference_strip();
  ShellModel copy = model;
  EXPECT_THROW(copy.add_support(Support::clamped("no_such_group")), InputError);
  ShellSection bad;
  bad.thickness = -1.0;
  bad.material = {1.0, 0.3, 1.0};
  EXPECT_THROW(ShellModel(model.mesh(), bad), InputError);
  bad.thickness = 1.0;
  bad.material.poisson = 0.5;
  EXPECT_THROW(ShellModel(model.mesh(), bad), InputError);
  bad.material.poisson = -1.0;
  EXPECT_THROW(ShellModel(model.mesh(), bad), InputError);
  bad.material.poisson = -0.3;  // auxetic: admissible (positive definite), as the case file allows
  EXPECT_NO_THROW(ShellModel(model.mesh(), bad));
  // A flipped element: reverse one triangle's orientation (kink in the nodal normals).
  mesh::Mesh flipped = model.mesh();
  auto& c = flipped.cells.connectivity;  // Tri10: swap vertices 1 and 2 and the edge nodes
  const std::array<int, 10> reorder{0, 2, 1, 8, 7, 6, 5, 4, 3, 9};
  std::array<Index, 10> first;
  for (int j = 0; j < 10; ++j)
    first[static_cast<std::size_t>(j)] = c[static_cast<std::size_t>(reorder[static_cast<std::size_t>(j)])];
  for (int j = 0; j < 10; ++j) c[static_cast<std::size_t>(j)] = first[static_cast<std::size_t>(j)];
  ShellSection good = model.section();
  EXPECT_THROW(ShellModel(flipped, good), InputError);
}

}  // namespace
}  // namespace shellflow::shell

#include "shellflow/shell/shell_queries.h"

namespace shellflow::shell {
namespace {

TEST(ShellQueries, PositionNormalAndInterpolationAtPoints) {
  const ShellModel model = reference_strip();
  Eigen::VectorXd u = Eigen::VectorXd::Zero(model.num_dofs());
  // A linear field: u(X) = (0, 0.1 x + 0.2 z, 0): exactly interpolated.
  for (Index n = 0; n < model.num_nodes(); ++n) {
    const Vec3& X = model.mesh().nodes[static_cast<std::size_t>(n)];
    u.segment<3>(7 * n) = Vec3(0.0, 0.1 * X.x() + 0.2 * X.z(), 0.0);
  }
  const ShellPoint p{7, Vec2(0.2, 0.3)};
  const Vec3 X = mid_surface_position(model, p, Eigen::VectorXd::Zero(model.num_dofs()));
  EXPECT_NEAR(X.y(), 0.0, 1e-15);
  const Vec3 x = mid_surface_position(model, p, u);
  EXPECT_NEAR(x.y(), 0.1 * X.x() + 0.2 * X.z(), 1e-14);
  EXPECT_NEAR((interpolate_nodal(model, p, u) - (x - X)).norm(), 0.0, 1e-15);
  // Normal: the directors' side (+y for this mesh), then tilted by the linear field.
  const Vec3 n0 = mid_surface_normal(model, p, Eigen::VectorXd::Zero(model.num_dofs()));
  EXPECT_NEAR(n0.dot(model.directors()[0]), 1.0, 1e-14);
  const Vec3 n = mid_surface_normal(model, p, u);
  EXPECT_NEAR(n.dot(Vec3(-0.1, 1.0, -0.2).normalized() * n0.y()), 1.0, 1e-14);
  EXPECT_THROW(mid_surface_position(model, {model.mesh().num_cells(), Vec2::Zero()}, u), InputError);
}

TEST(ShellQueries, HermiteInterpolationReproducesCubicMotion) {
  const auto x = [](double t) { return Vec3(1 + 2 * t - t * t * t, t * t, 3.0); };
  const auto v = [](double t) { return Vec3(2 - 3 * t * t, 2 * t, 0.0); };
  const double t0 = 0.3, dt = 0.2;
  for (double tau : {0.0, 0.25, 0.6, 1.0}) {
    const double t = t0 + tau * dt;
    EXPECT_LT((hermite_position(x(t0), v(t0), x(t0 + dt), v(t0 + dt), dt, tau) - x(t)).norm(), 1e-14);
    EXPECT_LT((hermite_velocity(x(t0), v(t0), x(t0 + dt), v(t0 + dt), dt, tau) - v(t)).norm(), 1e-13);
  }
}

}  // namespace
}  // namespace shellflow::shell

namespace shellflow::shell {
namespace {

TEST(ShellLoads, GravityTotalIsWeight) {
  ShellModel model = reference_strip();
  model.add_gravity(Vec3(0.0, -9.81, 0.0));
  Vec3 total = Vec3::Zero();
  for (Index n = 0; n < model.num_nodes(); ++n) total += model.reference_load().segment<3>(7 * n);
  EXPECT_NEAR(total.y() / (-9.81 * 2710.0 * 1.35e-3 * 0.5 * 0.025), 1.0, 1e-13);
  EXPECT_NEAR(total.x(), 0.0, 1e-15);
}

TEST(ShellLoads, LineLoadTotalIsLoadTimesLength) {
  ShellModel model = reference_strip();
  model.add_line_load({"sides", Vec3(0.0, 3.0, 0.0)});  // two edges of 0.5 m
  Vec3 total = Vec3::Zero();
  for (Index n = 0; n < model.num_nodes(); ++n) total += model.reference_load().segment<3>(7 * n);
  EXPECT_NEAR(total.y(), 3.0 * 1.0, 1e-13);
}

TEST(ShellLoads, EdgeCoupleStiffnessIsTheDerivativeOfItsForce) {
  ShellModel model = reference_strip();
  model.add_edge_couple({"trailing_edge", Vec3(0.0, 0.0, 1.0), 2.5});
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  Eigen::VectorXd u(model.num_dofs()), direction(model.num_dofs());
  for (Eigen::Index i = 0; i < u.size(); ++i) {
    u(i) = 0.3 * d(rng);  // finite director rotations
    direction(i) = d(rng);
  }
  SparseMatrix K = model.make_matrix();
  Eigen::VectorXd f = Eigen::VectorXd::Zero(model.num_dofs());
  model.add_follower_loads(u, 0.8, 0.0, f, &K);  // K holds -dF/du
  const double step = 1e-6;
  Eigen::VectorXd fp = Eigen::VectorXd::Zero(model.num_dofs()), fm = fp;
  model.add_follower_loads(u + step * direction, 0.8, 0.0, fp, nullptr);
  model.add_follower_loads(u - step * direction, 0.8, 0.0, fm, nullptr);
  const Eigen::VectorXd fd = (fp - fm) / (2 * step);
  const Eigen::VectorXd Kd = -(K * direction);
  EXPECT_LT((Kd - fd).norm() / fd.norm(), 1e-6);
  const Eigen::MatrixXd dense(K);
  EXPECT_LT((dense - dense.transpose()).norm() / dense.norm(), 1e-13);  // conservative couple
}

}  // namespace
}  // namespace shellflow::shell

#include "shellflow/shell/static_solver.h"

namespace shellflow::shell {
namespace {

TEST(ShellLoads, FollowerPressureTotalAndLoadStiffness) {
  ShellModel model = reference_strip();
  model.add_follower_pressure({"", 7.0});
  EXPECT_FALSE(model.symmetric_tangent());
  Eigen::VectorXd f = Eigen::VectorXd::Zero(model.num_dofs());
  model.add_follower_loads(Eigen::VectorXd::Zero(model.num_dofs()), 1.0, 0.0, f, nullptr);
  Vec3 total = Vec3::Zero();
  for (Index n = 0; n < model.num_nodes(); ++n) total += f.segment<3>(7 * n);
  const Vec3 expected = 7.0 * 0.5 * 0.025 * model.directors()[0];
  EXPECT_LT((total - expected).norm() / expected.norm(), 1e-13);

  std::mt19937 rng(9);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  Eigen::VectorXd u(model.num_dofs()), direction(model.num_dofs());
  for (Eigen::Index i = 0; i < u.size(); ++i) {
    u(i) = 0.003 * d(rng);
    direction(i) = 0.003 * d(rng);
  }
  SparseMatrix K = model.make_matrix();
  f.setZero();
  model.add_follower_loads(u, 0.6, 0.0, f, &K);  // K holds -dF/du
  const double step = 1e-7;
  Eigen::VectorXd fp = Eigen::VectorXd::Zero(model.num_dofs()), fm = fp;
  model.add_follower_loads(u + step * direction, 0.6, 0.0, fp, nullptr);
  model.add_follower_loads(u - step * direction, 0.6, 0.0, fm, nullptr);
  const Eigen::VectorXd fd = (fp - fm) / (2 * step);
  EXPECT_LT((-(K * direction) - fd).norm() / fd.norm(), 1e-6);
}

TEST(ShellLoads, SmallPressureOnClampedStripGivesPlateStripDeflection) {
  ShellModel model = reference_strip();
  const double p = 1.0, L = 0.5, D = 77.28e9 * std::pow(1.35e-3, 3) / (12.0 * (1.0 - 0.33 * 0.33));
  model.add_follower_pressure({"panel", p});
  StaticSolver solver(model);  // non-symmetric tangent: SparseLU path
  solver.run(1, 1.0);
  double w = 0.0;
  int count = 0;
  for (Index n = 0; n < model.num_nodes(); ++n)
    if (std::abs(model.mesh().nodes[static_cast<std::size_t>(n)].x() - 0.5) < 1e-9) {
      w += solver.displacement()(7 * n + 1) * model.directors()[0].y();
      ++count;
    }
  ASSERT_GT(count, 0);
  w /= count;
  const double w_theory = p * std::pow(L, 4) / (384.0 * D);
  std::printf("clamped strip, p = 1 Pa: midspan w = %.6e m, q L^4 / (384 D) = %.6e m\n", w, w_theory);
  EXPECT_NEAR(w / w_theory, 1.0, 2e-3);
}

}  // namespace
}  // namespace shellflow::shell

#include "structured_shell_mesh.h"

namespace shellflow::shell {
namespace {

/// Quarter of a unit cylinder about the x axis (directors point outwards), 3 x 3 cells.
ShellModel cylinder_patch() {
  ShellSection section;
  section.thickness = 0.01;
  section.material = {1e9, 0.3, 0.0};
  return ShellModel(testing::structured_shell_mesh(
                        1.0, 1.5, 3, 3, [](double s, double t) { return Vec3(s, std::sin(t), std::cos(t)); }),
                    section);
}

TEST(ShellLocator, PointsOffsetAlongTheNormalAreFoundAtTheirFoot) {
  const ShellModel model = cylinder_patch();
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.num_dofs());
  const ShellLocator locator(model);
  double worst_xi = 0.0, worst_distance = 0.0;
  for (Index e : {0, 5, 11, 17})
    for (const Vec2& xi : {Vec2(0.2, 0.3), Vec2(0.6, 0.1), Vec2(0.05, 0.9)})
      for (double d : {0.3, -0.25, 1e-3, 0.0}) {
        const ShellPoint foot{e, xi};
        const Vec3 p = mid_surface_position(model, foot, zero) + d * mid_surface_normal(model, foot, zero);
        const ClosestPoint c = locator.closest(p);
        EXPECT_EQ(c.point.element, e);
        worst_xi = std::max(worst_xi, (c.point.xi - xi).norm());
        worst_distance = std::max({worst_distance, std::abs(c.distance - std::abs(d)), std::abs(c.offset - d)});
      }
  std::printf("locator, cylinder: max |xi - xi_exact| %.2e, max distance/offset error %.2e\n", worst_xi,
              worst_distance);
  EXPECT_LT(worst_xi, 1e-10);
  EXPECT_LT(worst_distance, 1e-12);
}

TEST(ShellLocator, PointsBeyondAnEdgeProjectOntoTheEdge) {
  const ShellModel model = cylinder_patch();
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.num_dofs());
  const ShellLocator locator(model);
  // Structured mesh: cell 2 (cy nx + cx) of the last column has its edge 1 (ξ = (1 − s, s))
  // on the edge x = 1.
  const Index e = 2 * (1 * 3 + 2);
  for (double s : {0.15, 0.4, 0.8}) {
    const ShellPoint foot{e, Vec2(1.0 - s, s)};
    const Vec3 x = mid_surface_position(model, foot, zero);
    ASSERT_NEAR(x.x(), 1.0, 1e-14);
    const Vec3 n = mid_surface_normal(model, foot, zero);
    // Outward conormal: in the tangent plane, normal to the edge tangent.
    double dN[20];
    fem::Tri10::eval_gradients(foot.xi.data(), dN);
    Vec3 tangent = Vec3::Zero();  // d x̂ / ds along ξ = (1 − s, s)
    const auto conn = model.mesh().cells.element(e);
    for (int j = 0; j < 10; ++j)
      tangent +=
          (dN[2 * j + 1] - dN[2 * j]) * model.mesh().nodes[static_cast<std::size_t>(conn[static_cast<std::size_t>(j)])];
    Vec3 conormal = tangent.cross(n).normalized();
    if (conormal.x() < 0.0) conormal = -conormal;
    for (const auto& [out, d] : {std::pair{0.2, 0.1}, std::pair{0.05, -0.3}, std::pair{1.0, 0.0}}) {
      const Vec3 p = x + out * conormal + d * n;
      const ClosestPoint c = locator.closest(p);
      EXPECT_EQ(c.point.element, e);
      EXPECT_LT((c.point.xi - foot.xi).norm(), 1e-10) << "s = " << s;
      EXPECT_NEAR(c.distance, std::hypot(out, d), 1e-12);
      EXPECT_NEAR(c.offset, d, 1e-12);
    }
  }
  // Beyond a corner: the corner node.
  const Index corner_element = 2 * (2 * 3 + 2);  // last row and column; vertex 2 at (1, 1.5)
  const Vec3 corner = mid_surface_position(model, {corner_element, Vec2(0.0, 1.0)}, zero);
  const ClosestPoint c = locator.closest(corner + Vec3(0.3, 0.5, -0.1));
  EXPECT_LT((c.position - corner).norm(), 1e-12);
}

TEST(ShellLocator, DeformedStateIsSearchedInItsCurrentPositions) {
  const ShellModel model = cylinder_patch();
  const Mat3 R = Eigen::AngleAxisd(0.7, Vec3(1, 1, 0).normalized()).toRotationMatrix();
  const Vec3 shift(0.5, -1.0, 2.0);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(model.num_dofs());
  for (Index n = 0; n < model.num_nodes(); ++n) {
    const Vec3& X = model.mesh().nodes[static_cast<std::size_t>(n)];
    u.segment<3>(7 * n) = R * X + shift - X;
  }
  const ShellLocator locator(model, u);
  const ShellPoint foot{7, Vec2(0.25, 0.35)};
  const Vec3 p = mid_surface_position(model, foot, u) + 0.2 * mid_surface_normal(model, foot, u);
  const ClosestPoint c = locator.closest(p);
  EXPECT_EQ(c.point.element, foot.element);
  EXPECT_LT((c.point.xi - foot.xi).norm(), 1e-10);
  EXPECT_NEAR(c.offset, 0.2, 1e-12);
  EXPECT_THROW(locator.closest(Vec3(std::nan(""), 0.0, 0.0)), InputError);
  EXPECT_THROW(ShellLocator(model, Eigen::VectorXd::Zero(3)), InputError);
}

}  // namespace
}  // namespace shellflow::shell
