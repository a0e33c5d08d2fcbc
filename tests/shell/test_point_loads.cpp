// Load points and the loads the coupling sets on them (shell_model.h): the load points are
// the pressure kernel's quadrature points; point pressures equal a group follower pressure
// of the same value (force, tangent, static and dynamic solves); the point-pressure tangent
// against finite differences on a cylinder; point tractions against a surface traction;
// the time history of a follower pressure (cavity) at each scheme's evaluation time.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "reference_strip.h"
#include "shellflow/core/error.h"
#include "shellflow/shell/newmark_solver.h"
#include "shellflow/shell/shell_queries.h"
#include "shellflow/shell/static_solver.h"
#include "structured_shell_mesh.h"

namespace shellflow::shell {
namespace {

/// A quarter of a cylinder of radius 1 about the x axis, 3 x 3 cubic cells (normals outwards).
ShellModel cylinder() {
  ShellSection section;
  section.thickness = 0.01;
  section.material = {1e9, 0.3, 1000.0};
  ShellModel model(testing::structured_shell_mesh(1.0, 0.5 * std::numbers::pi, 3, 3,
                                                  [](double s, double t) { return Vec3(s, std::sin(t), std::cos(t)); }),
                   section);
  model.add_support(Support::clamped("left"));
  return model;
}

Eigen::VectorXd random_vector(Eigen::Index n, double scale, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  Eigen::VectorXd v(n);
  for (Eigen::Index i = 0; i < n; ++i) v(i) = scale * d(rng);
  return v;
}

double relative(const Eigen::VectorXd& a, const Eigen::VectorXd& b) { return (a - b).norm() / b.norm(); }

TEST(LoadPoints, AreTheQuadraturePointsElementMajorWithTheReferenceArea) {
  const ShellModel model = reference_strip();
  const auto& points = model.load_points();
  const int nq = fem::triangle_rule(model.section().plane_degree).size();
  ASSERT_EQ(points.size(), static_cast<std::size_t>(model.mesh().num_cells() * nq));
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.num_dofs());
  double area = 0.0;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const LoadPoint& p = points[k];
    EXPECT_EQ(p.point.element, static_cast<Index>(k / static_cast<std::size_t>(nq)));
    const auto xi =
        fem::triangle_rule(model.section().plane_degree).point(static_cast<int>(k % static_cast<std::size_t>(nq)));
    EXPECT_EQ(p.point.xi, Vec2(xi[0], xi[1]));
    EXPECT_LT((p.position - mid_surface_position(model, p.point, zero)).norm(), 1e-15);
    EXPECT_LT((p.normal - mid_surface_normal(model, p.point, zero)).norm(), 1e-14);
    EXPECT_GT(p.normal.dot(model.directors()[0]), 0.999);
    area += p.weight;
  }
  EXPECT_NEAR(area / (0.5 * 0.025), 1.0, 1e-13);

  const ShellModel curved = cylinder();
  double curved_area = 0.0;
  for (const LoadPoint& p : curved.load_points()) {
    curved_area += p.weight;
    EXPECT_GT(p.normal.dot(Vec3(0.0, p.position.y(), p.position.z()).normalized()), 0.999);  // outwards, like V
  }
  EXPECT_NEAR(curved_area / (0.5 * std::numbers::pi), 1.0, 3e-5);  // cubic arcs, 3 cells around
}

TEST(PointPressure, UniformEqualsTheGroupFollowerPressure) {
  ShellModel group = reference_strip(), points = reference_strip();
  group.add_follower_pressure({"", 7.0});
  points.set_point_pressure(std::vector<double>(points.load_points().size(), 7.0));
  EXPECT_FALSE(points.symmetric_tangent());
  const Eigen::VectorXd u = random_vector(group.num_dofs(), 0.003, 3);
  SparseMatrix Kg = group.make_matrix(), Kp = points.make_matrix();
  Eigen::VectorXd fg = Eigen::VectorXd::Zero(group.num_dofs()), fp = fg;
  group.add_follower_loads(u, 1.0, 0.0, fg, &Kg);
  points.add_follower_loads(u, 0.25, 3.0, fp, &Kp);  // point loads: no load factor, no time
  EXPECT_LT(relative(fp, fg), 1e-12);
  const Eigen::Map<const Eigen::VectorXd> vg(Kg.valuePtr(), Kg.nonZeros()), vp(Kp.valuePtr(), Kp.nonZeros());
  EXPECT_GT(vg.norm(), 0.0);
  EXPECT_LT(relative(vp, vg), 1e-12);

  // Sizes are checked; clearing removes them.
  EXPECT_THROW(points.set_point_pressure(std::vector<double>(3, 1.0)), InputError);
  EXPECT_THROW(points.set_point_traction(std::vector<Vec3>(points.load_points().size() + 1, Vec3::Zero())), InputError);
  points.clear_point_loads();
  EXPECT_TRUE(points.symmetric_tangent());
  EXPECT_FALSE(points.has_follower_loads());
}

TEST(PointPressure, TangentMatchesFiniteDifferencesOnACylinder) {
  ShellModel model = cylinder();
  std::vector<double> p;
  for (const LoadPoint& lp : model.load_points())
    p.push_back(1e3 * (1.0 + lp.position.x() - 2.0 * lp.position.y() * lp.position.z()));
  model.set_point_pressure(p);
  const Eigen::VectorXd u = random_vector(model.num_dofs(), 0.01, 11);
  const Eigen::VectorXd direction = random_vector(model.num_dofs(), 1.0, 12);
  SparseMatrix K = model.make_matrix();
  Eigen::VectorXd f = Eigen::VectorXd::Zero(model.num_dofs());
  model.add_follower_loads(u, 1.0, 0.0, f, &K);  // K holds -dF/du
  const double h = 1e-6;
  Eigen::VectorXd fp = Eigen::VectorXd::Zero(model.num_dofs()), fm = fp;
  model.add_follower_loads(u + h * direction, 1.0, 0.0, fp, nullptr);
  model.add_follower_loads(u - h * direction, 1.0, 0.0, fm, nullptr);
  const Eigen::VectorXd fd = (fp - fm) / (2.0 * h);
  const double error = relative(-(K * direction), fd);
  std::printf("point pressure tangent vs central differences: rel. error %.2e\n", error);
  EXPECT_LT(error, 1e-7);
  const Eigen::MatrixXd dense(K);
  EXPECT_GT((dense - dense.transpose()).norm(), 1e-3 * dense.norm());  // not symmetric

  // Total force at the reference state = Σ p_q n_q w_q.
  Eigen::VectorXd f0 = Eigen::VectorXd::Zero(model.num_dofs());
  model.add_follower_loads(Eigen::VectorXd::Zero(model.num_dofs()), 1.0, 0.0, f0, nullptr);
  Vec3 total = Vec3::Zero(), expected = Vec3::Zero();
  for (Index n = 0; n < model.num_nodes(); ++n) total += f0.segment<3>(7 * n);
  for (std::size_t k = 0; k < p.size(); ++k)
    expected += p[k] * model.load_points()[k].weight * model.load_points()[k].normal;
  EXPECT_LT((total - expected).norm() / expected.norm(), 1e-13);
}

TEST(PointTraction, EqualsTheSurfaceTraction) {
  ShellModel dead = cylinder(), points = cylinder();
  const Vec3 t(3.0, -1.0, 2.0);
  dead.add_surface_traction({"", t});
  points.set_point_traction(std::vector<Vec3>(points.load_points().size(), t));
  Eigen::VectorXd f = Eigen::VectorXd::Zero(points.num_dofs());
  SparseMatrix K = points.make_matrix();
  points.add_follower_loads(random_vector(points.num_dofs(), 0.01, 1), 0.0, 0.0, f, &K);
  EXPECT_LT(relative(f, dead.reference_load()), 1e-13);
  EXPECT_EQ(Eigen::Map<const Eigen::VectorXd>(K.valuePtr(), K.nonZeros()).norm(), 0.0);  // dead
  EXPECT_TRUE(points.symmetric_tangent());
}

TEST(PointPressure, StaticSolveEqualsTheFollowerPressureOne) {
  ShellModel group = reference_strip(), points = reference_strip();
  group.add_follower_pressure({"", 50.0});
  points.set_point_pressure(std::vector<double>(points.load_points().size(), 50.0));
  StaticSolver a(group), b(points);
  a.run(1, 1.0);
  b.run(1, 1.0);
  EXPECT_GT(a.displacement().norm(), 0.0);
  EXPECT_LT(relative(b.displacement(), a.displacement()), 1e-12);
}

TEST(PointPressure, NewmarkStepsEqualTheFollowerPressureOnes) {
  ShellModel group = reference_strip(), points = reference_strip();
  group.add_follower_pressure({"", 50.0});
  points.set_point_pressure(std::vector<double>(points.load_points().size(), 50.0));
  for (TimeScheme scheme : {TimeScheme::newmark, TimeScheme::midpoint}) {
    NewmarkOptions options;
    options.scheme = scheme;
    NewmarkSolver a(group, options, [](double) { return 1.0; }), b(points, options);
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(group.num_dofs());
    a.set_initial_state(zero, zero);
    b.set_initial_state(zero, zero);
    EXPECT_LT(relative(b.acceleration(), a.acceleration()), 1e-12);
    for (int s = 0; s < 4; ++s) {
      a.advance(1e-4);
      b.advance(1e-4);
    }
    EXPECT_GT(a.displacement().norm(), 0.0);
    EXPECT_LT(relative(b.displacement(), a.displacement()), 1e-12);
    EXPECT_LT(relative(b.velocity(), a.velocity()), 1e-12);
  }
}

TEST(PointPressure, ChangedBetweenStepsActsFromTheNextStep) {
  ShellModel model = reference_strip();
  NewmarkSolver solver(model);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.num_dofs());
  solver.set_initial_state(zero, zero);
  solver.advance(1e-4);
  EXPECT_EQ(solver.displacement().norm(), 0.0);
  model.set_point_pressure(std::vector<double>(model.load_points().size(), 50.0));
  solver.advance(1e-4);
  EXPECT_GT(solver.displacement().norm(), 0.0);
}

/// Displacement norms after each of `steps` steps of dt for a follower pressure whose
/// history is a unit step at t_on (load factor 0 throughout).
std::vector<double> stepped_history_run(TimeScheme scheme, double t_on, int steps, double dt) {
  ShellModel model = reference_strip();
  FollowerPressure cavity{"", 50.0, TimeFunction::step(1.0, t_on)};
  model.add_follower_pressure(cavity);
  NewmarkOptions options;
  options.scheme = scheme;
  NewmarkSolver solver(model, options);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.num_dofs());
  solver.set_initial_state(zero, zero);
  std::vector<double> norms{solver.acceleration().norm()};
  for (int s = 0; s < steps; ++s) {
    solver.advance(dt);
    norms.push_back(solver.displacement().norm());
  }
  return norms;
}

TEST(PressureHistory, IsEvaluatedAtEachSchemesOwnTime) {
  const double dt = 1e-4;
  // Newmark: at t_{n+1}. A step at 2.6 dt first acts in step 3 (t = 3 dt).
  const auto newmark = stepped_history_run(TimeScheme::newmark, 2.6 * dt, 4, dt);
  EXPECT_EQ(newmark[0], 0.0);
  EXPECT_EQ(newmark[2], 0.0);
  EXPECT_GT(newmark[3], 0.0);
  // Midpoint: at t_mid; step 3 has t_mid = 2.5 dt < 2.6 dt, step 4 loads.
  const auto midpoint = stepped_history_run(TimeScheme::midpoint, 2.6 * dt, 4, dt);
  EXPECT_EQ(midpoint[3], 0.0);
  EXPECT_GT(midpoint[4], 0.0);
  // set_initial_state: at t0.
  EXPECT_GT(stepped_history_run(TimeScheme::newmark, 0.0, 0, dt)[0], 0.0);

  // Same as a pressure without history scaled by a load factor with the same step.
  ShellModel model = reference_strip();
  model.add_follower_pressure({"", 50.0});
  NewmarkSolver scaled(model, {}, [&](double t) { return t >= 2.6 * dt ? 1.0 : 0.0; });
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.num_dofs());
  scaled.set_initial_state(zero, zero);
  for (int s = 0; s < 4; ++s) scaled.advance(dt);
  EXPECT_NEAR(scaled.displacement().norm() / newmark[4], 1.0, 1e-12);
}

TEST(PressureHistory, StaticRunsUseTheLoadFactorAsTime) {
  // p h(λ) with h(λ) = 2 λ²: at λ = 0.5 the pressure is 0.5 p, as a plain pressure p at 0.5.
  ShellModel history = reference_strip(), plain = reference_strip();
  history.add_follower_pressure({"", 50.0, TimeFunction::expression("2*t^2")});
  plain.add_follower_pressure({"", 50.0});
  StaticSolver a(history), b(plain);
  ASSERT_GT(a.solve(0.5), 0);
  ASSERT_GT(b.solve(0.5), 0);
  EXPECT_LT(relative(a.displacement(), b.displacement()), 1e-12);
  // ∂F/∂λ = p h'(λ) n dA = 2 p n dA at λ = 0.5: twice the plain direction.
  Eigen::VectorXd qa = a.load_direction(), qb = b.load_direction();
  EXPECT_LT(relative(qa, Eigen::VectorXd(2.0 * qb)), 1e-12);
}

}  // namespace
}  // namespace shellflow::shell
