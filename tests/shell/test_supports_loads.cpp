// Supports along arbitrary directions (local bases, shell.md §10), hard simple support,
// prescribed motion, dead surface traction (§11), and bad input of supports and loads.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "shellflow/core/error.h"
#include "shellflow/shell/linear_solver.h"
#include "shellflow/shell/newmark_solver.h"
#include "shellflow/shell/shell_model.h"
#include "shellflow/shell/static_solver.h"
#include "structured_shell_mesh.h"

namespace shellflow::shell {
namespace {

constexpr double young = 1e9, poisson = 0.3, thickness = 0.01;

ShellSection section() {
  ShellSection s;
  s.thickness = thickness;
  s.material = {young, poisson, 0.0};
  return s;
}

/// Strip [0, L] x [0, W] in the plane z = 0, then rotated by R and shifted.
ShellModel strip(const Mat3& R, double L = 1.0, double W = 0.1, int nx = 8, int ny = 1) {
  const Vec3 shift(0.3, -0.7, 1.1);
  return ShellModel(testing::structured_shell_mesh(
                        L, W, nx, ny, [&](double s, double t) { return Vec3(R * Vec3(s, t, 0.0) + shift); }),
                    section());
}

/// Equilibrium at `load_factor` from the state u with the StaticSolver, which brings the
/// Newton system to the model's local bases (to_local / to_global) and moves prescribed
/// supports to their values at the load factor (the pseudo-time of a static run).
/// Returns the number of iterations, -1 without convergence.
int solve(const ShellModel& model, Eigen::VectorXd& u, double load_factor = 1.0) {
  NewtonOptions options;
  options.tolerance = 1e-11;
  options.residual_tolerance = 1e-9;
  options.max_iterations = 30;
  StaticSolver solver(model, options);
  solver.set_state(u, load_factor);
  const int iterations = solver.solve(load_factor);
  if (iterations > 0) u = solver.displacement();
  return iterations;
}

/// max |u_b − Q u_a| over all nodal 3-vectors, relative to max |u_a|; a compared directly.
double rotated_difference(const Eigen::VectorXd& ua, const Eigen::VectorXd& ub, const Mat3& Q) {
  double diff = 0.0;
  for (Eigen::Index n = 0; n < ua.size() / 7; ++n) {
    diff = std::max(diff, (ub.segment<3>(7 * n) - Q * ua.segment<3>(7 * n)).norm());
    diff = std::max(diff, (ub.segment<3>(7 * n + 3) - Q * ua.segment<3>(7 * n + 3)).norm());
    diff = std::max(diff, std::abs(ub(7 * n + 6) - ua(7 * n + 6)));
  }
  return diff / ua.cwiseAbs().maxCoeff();
}

TEST(ShellSupports, LocalBasisTransformIsTransposeKTimesT) {
  const Mat3 R = Eigen::AngleAxisd(0.6, Vec3(1, 2, 2).normalized()).toRotationMatrix();
  ShellModel model = strip(R, 1.0, 0.1, 2, 1);
  EXPECT_FALSE(model.has_local_frames());
  model.add_support(DirectionalSupport::symmetry_plane("bottom", R * Vec3::UnitY()));
  model.add_support(DirectionalSupport::roller("right", R * Vec3(1.0, 0.5, 0.0), false));
  ASSERT_TRUE(model.has_local_frames());
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  Eigen::VectorXd u(model.num_dofs());
  for (Eigen::Index i = 0; i < u.size(); ++i) u(i) = 1e-3 * d(rng);
  SparseMatrix K = model.make_matrix();
  Eigen::VectorXd f;
  ASSERT_TRUE(model.assemble(u, f, &K));
  // Dense T from to_global applied to unit vectors.
  Eigen::MatrixXd T(model.num_dofs(), model.num_dofs());
  for (Eigen::Index i = 0; i < T.cols(); ++i) {
    Eigen::VectorXd e = Eigen::VectorXd::Unit(model.num_dofs(), i);
    model.to_global(e);
    T.col(i) = e;
  }
  EXPECT_LT((T.transpose() * T - Eigen::MatrixXd::Identity(T.rows(), T.cols())).norm(), 1e-13);
  const Eigen::MatrixXd expected = T.transpose() * Eigen::MatrixXd(K) * T;
  model.to_local(K);
  EXPECT_LT((Eigen::MatrixXd(K) - expected).norm() / expected.norm(), 1e-14);
  Eigen::VectorXd local = f;
  model.to_local(local);
  EXPECT_LT((local - T.transpose() * f).norm(), 1e-12 * f.norm());
  // The fixed local components are the constrained directions: Tᵀ n on the bottom edge.
  const Index node = model.mesh().group("bottom").nodes[1];
  const Vec3 n = R * Vec3::UnitY();
  const Eigen::Matrix3d Tn = T.block<3, 3>(7 * node, 7 * node);
  int fixed = 0;
  for (int i = 0; i < 3; ++i)
    if (model.constrained()[static_cast<std::size_t>(7 * node + i)]) {
      EXPECT_NEAR(std::abs(Tn.col(i).dot(n)), 1.0, 1e-14);
      ++fixed;
    }
  EXPECT_EQ(fixed, 1);
}

/// Clamped left end, symmetry planes on the long edges, right end on a roller along the
/// strip with clamped director: along the axes (Support) or along Q's axes (directional).
void add_roller_strip_supports(ShellModel& model, const Mat3& Q, bool directional) {
  model.add_support(Support::clamped("left"));
  if (directional) {
    model.add_support(DirectionalSupport::symmetry_plane("bottom", Q * Vec3::UnitY()));
    model.add_support(DirectionalSupport::symmetry_plane("top", Q * Vec3::UnitY()));
    model.add_support(DirectionalSupport::roller("right", Q * Vec3::UnitX(), true));
  } else {
    model.add_support(Support::symmetry_plane("bottom", 1));
    model.add_support(Support::symmetry_plane("top", 1));
    model.add_support(Support::sliding("right", 0, true));
  }
}

/// Cantilever strip in cylindrical bending (symmetry planes on the long edges), its right
/// end on a roller along the strip with clamped director, loaded by a traction normal to the
/// strip and an axial pull. The same model rotated by Q, with the planes and the roller along
/// the rotated directions, must give Q times the displacements.
Eigen::VectorXd roller_strip(const Mat3& Q, bool directional, int* iterations) {
  ShellModel model = strip(Q);
  add_roller_strip_supports(model, Q, directional);
  model.add_surface_traction({"", Q * Vec3(0.0, 0.0, 2e3)});  // deflection ~ h: nonlinear
  model.add_line_load({"right", Q * Vec3(1e5, 0.0, 0.0)});
  Eigen::VectorXd u = Eigen::VectorXd::Zero(model.num_dofs());
  *iterations = solve(model, u);
  return u;
}

TEST(ShellSupports, RotatedSymmetryPlanesAndRollerGiveTheRotatedSolution) {
  int it_axis = 0, it_rotated = 0;
  const Eigen::VectorXd ua = roller_strip(Mat3::Identity(), false, &it_axis);
  const Mat3 Q = Eigen::AngleAxisd(0.8, Vec3(0.2, -1.0, 0.6).normalized()).toRotationMatrix();
  const Eigen::VectorXd ub = roller_strip(Q, true, &it_rotated);
  ASSERT_GT(it_axis, 0);
  ASSERT_GT(it_rotated, 0);
  double w_mid = 0.0;
  for (Eigen::Index n = 0; n < ua.size() / 7; ++n) w_mid = std::max(w_mid, std::abs(ua(7 * n + 2)));
  const double diff = rotated_difference(ua, ub, Q);
  std::printf("rotated supports: Newton iterations %d (axes) / %d (rotated), max |w| %.3e m, rel. difference %.2e\n",
              it_axis, it_rotated, w_mid, diff);
  EXPECT_GT(w_mid, 0.2 * thickness);  // with the axial pull: 9 Newton iterations
  EXPECT_LT(diff, 1e-9);
}

TEST(ShellSupports, HardSimpleSupportOnAnObliqueStripGivesPlateStripBending) {
  // Strip rotated about z by 30° (edge tangents not along axes) and tilted: hard simple
  // supports at both ends, symmetry planes on the long edges, uniform normal traction.
  const Mat3 Q = (Eigen::AngleAxisd(0.4, Vec3::UnitX()) * Eigen::AngleAxisd(std::numbers::pi / 6, Vec3::UnitZ()))
                     .toRotationMatrix();
  ShellModel model = strip(Q, 1.0, 0.1, 8, 1);
  model.add_hard_simple_support("left");
  model.add_hard_simple_support("right");
  model.add_support(DirectionalSupport::symmetry_plane("bottom", Q * Vec3::UnitY()));
  model.add_support(DirectionalSupport::symmetry_plane("top", Q * Vec3::UnitY()));
  const double p = 1.0;  // tiny: linear
  model.add_surface_traction({"shell", Q * Vec3(0.0, 0.0, p)});
  Eigen::VectorXd u = Eigen::VectorXd::Zero(model.num_dofs());
  ASSERT_GT(solve(model, u), 0);
  const Vec3 normal = Q * Vec3::UnitZ(), edge_tangent = Q * Vec3::UnitY();
  double w = 0.0, worst_tilt = 0.0, worst_edge = 0.0;
  int count = 0;
  for (Index n = 0; n < model.num_nodes(); ++n) {
    const double s = (model.mesh().nodes[static_cast<std::size_t>(n)] - Vec3(0.3, -0.7, 1.1)).dot(Q * Vec3::UnitX());
    if (std::abs(s - 0.5) < 1e-9) {
      w += u.segment<3>(7 * n).dot(normal);
      ++count;
    }
    if (s < 1e-9 || s > 1.0 - 1e-9) {
      worst_tilt = std::max(worst_tilt, std::abs(u.segment<3>(7 * n + 3).dot(edge_tangent)));
      worst_edge = std::max(worst_edge, u.segment<3>(7 * n).norm());
    }
  }
  ASSERT_GT(count, 0);
  w /= count;
  const double D = young * std::pow(thickness, 3) / (12.0 * (1.0 - poisson * poisson));
  const double shear = p / (8.0 * 5.0 / 6.0 * young / (2.0 * (1.0 + poisson)) * thickness);
  const double w_theory = 5.0 * p / (384.0 * D) + shear;
  std::printf("hard simple support, oblique strip: midspan w %.6e, 5pL^4/(384D) + shear %.6e (ratio %.6f)\n", w,
              w_theory, w / w_theory);
  EXPECT_NEAR(w / w_theory, 1.0, 2e-3);
  EXPECT_EQ(worst_edge, 0.0);
  EXPECT_LT(worst_tilt, 1e-14);
}

TEST(ShellSupports, PrescribedRotationAboutTheClampedEdgeMovesTheStripRigidly) {
  ShellModel model = strip(Mat3::Identity(), 1.0, 0.1, 4, 1);
  const Vec3 d(0.1, 0.2, -0.3);
  PrescribedMotion motion;
  motion.group = "left";
  motion.displacement = d;
  motion.displacement_history = TimeFunction::ramp(1.0, 2.0);
  motion.rotation_axis = Vec3(0.0, 2.0, 0.0);  // along the edge; normalised by the model
  motion.rotation_angle = TimeFunction::ramp(1.2, 2.0);
  model.add_prescribed_motion(motion);
  ASSERT_TRUE(model.has_prescribed_motion());
  Eigen::VectorXd u = Eigen::VectorXd::Zero(model.num_dofs());
  for (double t : {0.25, 0.5, 0.75, 1.0}) ASSERT_GT(solve(model, u, t), 0) << "t = " << t;
  // At t = 1: translation d/2, rotation 0.6 rad about y through the edge x = 0.3, z = 1.1.
  const Mat3 R = Eigen::AngleAxisd(0.6, Vec3::UnitY()).toRotationMatrix();
  const Vec3 pivot(0.3, 0.0, 1.1);
  double worst = 0.0;
  for (Index n = 0; n < model.num_nodes(); ++n) {
    const Vec3& X = model.mesh().nodes[static_cast<std::size_t>(n)];
    const Vec3& V = model.directors()[static_cast<std::size_t>(n)];
    Vec3 arm = X - pivot;
    arm.y() = 0.0;
    const Vec3 x = X + (R * arm - arm) + 0.5 * d;
    worst = std::max({worst, (X + u.segment<3>(7 * n) - x).norm(), (u.segment<3>(7 * n + 3) - (R * V - V)).norm()});
  }
  std::printf("prescribed rigid rotation: max deviation from the rigid motion %.2e\n", worst);
  EXPECT_LT(worst, 1e-10);
}

TEST(ShellSupports, DynamicsWithRotatedSupportsGivesTheRotatedMotion) {
  // The roller strip of the static test, with mass, suddenly loaded: Newmark and the
  // midpoint rule on the rotated model must give Q times the axis-aligned motion.
  for (const TimeScheme scheme : {TimeScheme::newmark, TimeScheme::midpoint}) {
    const auto run = [&](const Mat3& Q, bool directional) {
      ShellSection s = section();
      s.material.density = 2700.0;
      ShellModel model(
          testing::structured_shell_mesh(1.0, 0.1, 6, 1, [&](double x, double y) { return Vec3(Q * Vec3(x, y, 0.0)); }),
          s);
      add_roller_strip_supports(model, Q, directional);
      model.add_surface_traction({"", Q * Vec3(0.0, 0.0, 2e3)});
      NewmarkOptions options;
      options.scheme = scheme;
      options.newton.tolerance = 1e-11;
      options.newton.residual_tolerance = 1e-9;
      NewmarkSolver solver(model, options, [](double) { return 1.0; });
      const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.num_dofs());
      solver.set_initial_state(zero, zero);
      for (int step = 0; step < 10; ++step) solver.advance(2e-4);
      return solver.displacement();
    };
    const Mat3 Q = Eigen::AngleAxisd(0.8, Vec3(0.2, -1.0, 0.6).normalized()).toRotationMatrix();
    const Eigen::VectorXd ua = run(Mat3::Identity(), false);
    const Eigen::VectorXd ub = run(Q, true);
    const double diff = rotated_difference(ua, ub, Q);
    std::printf("rotated supports, %s: max |u| %.3e m after 10 steps, rel. difference %.2e\n",
                scheme == TimeScheme::newmark ? "Newmark" : "midpoint", ua.cwiseAbs().maxCoeff(), diff);
    EXPECT_GT(ua.cwiseAbs().maxCoeff(), 1e-4);
    EXPECT_LT(diff, 1e-9);
  }
}

TEST(ShellSupports, PrescribedTranslationAtConstantVelocityIsFollowedExactly) {
  // The left edge moves at constant velocity d and the free strip starts with velocity d:
  // the exact motion is the rigid translation u = d t, which both schemes integrate
  // exactly (linear in time) once the prescribed dofs get their positions and rates.
  for (const TimeScheme scheme : {TimeScheme::newmark, TimeScheme::midpoint}) {
    ShellSection s = section();
    s.material.density = 2700.0;
    ShellModel model(testing::structured_shell_mesh(1.0, 0.1, 4, 1, [](double x, double y) { return Vec3(x, y, 0.0); }),
                     s);
    const Vec3 d(0.3, -0.2, 0.5);
    PrescribedMotion motion;
    motion.group = "left";
    motion.displacement = d;
    motion.displacement_history = TimeFunction::ramp(10.0, 10.0);  // f(t) = t up to t = 10
    model.add_prescribed_motion(motion);
    NewmarkOptions options;
    options.scheme = scheme;
    NewmarkSolver solver(model, options);
    Eigen::VectorXd v = Eigen::VectorXd::Zero(model.num_dofs());
    for (Index n = 0; n < model.num_nodes(); ++n) v.segment<3>(7 * n) = d;
    solver.set_initial_state(Eigen::VectorXd::Zero(model.num_dofs()), v);
    for (int step = 0; step < 10; ++step) solver.advance(1e-3);
    double worst = 0.0;
    for (Index n = 0; n < model.num_nodes(); ++n) {
      worst = std::max(worst, (solver.displacement().segment<3>(7 * n) - 0.01 * d).norm() / (0.01 * d.norm()));
      worst = std::max(worst, (solver.velocity().segment<3>(7 * n) - d).norm() / d.norm());
      worst = std::max(worst, solver.displacement().segment<3>(7 * n + 3).norm());
    }
    std::printf("prescribed translation, %s: max relative deviation from u = d t, v = d: %.2e\n",
                scheme == TimeScheme::newmark ? "Newmark" : "midpoint", worst);
    EXPECT_LT(worst, 1e-10);
  }
}

TEST(ShellSupports, PrescribedMotionNeedsLoadControl) {
  ShellModel model = strip(Mat3::Identity(), 1.0, 0.1, 2, 1);
  PrescribedMotion motion;
  motion.group = "left";
  motion.displacement = Vec3(0.0, 0.0, 0.01);
  model.add_prescribed_motion(motion);
  model.add_point_load({model.num_nodes() - 1, Vec3(0.0, 0.0, 1.0)});
  StaticSolver solver(model);
  ArcLengthOptions arc;
  try {
    solver.run_arc_length(2, arc);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("use control: load"), std::string::npos) << e.what();
  }
}

TEST(ShellLoads, SurfaceTractionTotalIsTractionTimesArea) {
  // Quarter-ish cylinder of radius 1, arc 1.5, length 2: area 3 (the cubic mesh represents
  // the arc up to its interpolation error, which converges at O(h^4)).
  const Vec3 t(0.5, -2.0, 3.0);
  double previous = 0.0;
  for (int ny : {3, 6}) {
    ShellModel model(testing::structured_shell_mesh(
                         2.0, 1.5, 2, ny, [](double s, double a) { return Vec3(s, std::sin(a), std::cos(a)); }),
                     section());
    model.add_surface_traction({"shell", t});
    Vec3 total = Vec3::Zero();
    for (Index n = 0; n < model.num_nodes(); ++n) total += model.reference_load().segment<3>(7 * n);
    const double error = (total - 3.0 * t).norm() / (3.0 * t.norm());
    std::printf("surface traction on a cylinder, %d cells around: rel. error of the total %.3e\n", ny, error);
    EXPECT_LT(error, 2e-5);
    if (previous > 0.0) {
      EXPECT_GT(previous / error, 10.0);  // O(h^4): 16 expected
    }
    previous = error;
    // The whole shell (empty group) gives the same loads.
    ShellModel whole = model;
    whole.add_surface_traction({"", t});
    EXPECT_LT((whole.reference_load() - 2.0 * model.reference_load()).norm(), 1e-12 * model.reference_load().norm());
  }
  // Flat plate: exact.
  ShellModel plate(testing::structured_shell_mesh(1.0, 0.5, 2, 2, [](double s, double a) { return Vec3(s, a, 0.0); }),
                   section());
  plate.add_surface_traction({"", t});
  Vec3 total = Vec3::Zero();
  for (Index n = 0; n < plate.num_nodes(); ++n) total += plate.reference_load().segment<3>(7 * n);
  EXPECT_LT((total - 0.5 * t).norm(), 1e-14);
}

TEST(ShellSupports, BadInputStopsWithAMessage) {
  ShellModel model = strip(Mat3::Identity(), 1.0, 0.1, 2, 1);
  const auto message = [](auto&& f) {
    try {
      f();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  // A missing group: the message names it, the mesh and the groups available.
  const std::string missing =
      message([&] { model.add_support(DirectionalSupport::symmetry_plane("wall", Vec3::UnitX())); });
  EXPECT_NE(missing.find("'wall'"), std::string::npos) << missing;
  EXPECT_NE(missing.find("shell"), std::string::npos) << missing;
  EXPECT_NE(missing.find("left, right, bottom, top"), std::string::npos) << missing;
  EXPECT_NE(message([&] { model.add_hard_simple_support("wall"); }).find("'wall'"), std::string::npos);
  EXPECT_NE(message([&] { model.add_surface_traction({"wall", Vec3::UnitZ()}); }).find("'wall'"), std::string::npos);
  EXPECT_NE(message([&] { model.add_prescribed_motion({"wall", Vec3::UnitZ()}); }).find("'wall'"), std::string::npos);
  // Zero / NaN traction, a surface load on a line group.
  EXPECT_NE(message([&] { model.add_surface_traction({"shell", Vec3::Zero()}); }).find("zero"), std::string::npos);
  EXPECT_NE(message([&] {
              model.add_surface_traction({"", Vec3(1.0, std::nan(""), 0.0)});
            }).find("not finite"),
            std::string::npos);
  EXPECT_NE(message([&] {
              model.add_surface_traction({"left", Vec3::UnitZ()});
            }).find("surface group"),
            std::string::npos);
  // Directions of zero length.
  EXPECT_NE(message([&] {
              model.add_support(DirectionalSupport::symmetry_plane("left", Vec3::Zero()));
            }).find("non-zero length"),
            std::string::npos);
  EXPECT_NE(message([&] { DirectionalSupport::roller("left", Vec3::Zero(), true); }).find("non-zero length"),
            std::string::npos);
  PrescribedMotion spin{"left", Vec3::Zero()};
  spin.rotation_axis = Vec3(std::nan(""), 0.0, 0.0);
  EXPECT_NE(message([&] { model.add_prescribed_motion(spin); }).find("non-zero length"), std::string::npos);
  // A hard simple support needs lines.
  EXPECT_NE(message([&] { model.add_hard_simple_support("shell"); }).find("group of lines"), std::string::npos);
  EXPECT_FALSE(model.has_local_frames());  // nothing was added by the failed calls
}

}  // namespace
}  // namespace shellflow::shell
