// Path following (shell.md §7 "Statics"): displacement control and the cylindrical
// arc-length method. Before a limit point both reproduce load control (Sze 3.1 strip);
// through the snap-through of the hinged cylindrical roof of Sze, Liu & Lo (2004) the two
// methods trace the same equilibrium path, in equilibrium at every point, with the load
// rising, falling and rising again. The limit load is checked for mesh convergence.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

#include "reference_strip.h"
#include "shellflow/core/error.h"
#include "shellflow/mesh/gmsh_io.h"
#include "shellflow/shell/static_solver.h"

namespace shellflow::shell {
namespace {

ShellModel sze31_model() {
  ShellSection section;
  section.thickness = 0.1;
  section.material = {1.2e6, 0.0, 0.0};
  ShellModel model(cubic_mesh("sze31_cantilever_8x1.geo"), section);
  model.add_support(Support::clamped("clamped"));
  model.add_line_load({"tip", Vec3(0.0, 0.0, 4.0)});  // P_max = 4 over b = 1
  return model;
}

double relative_difference(const Eigen::VectorXd& a, const Eigen::VectorXd& b) { return (a - b).norm() / b.norm(); }

// Sze 3.1 has no limit point: the arc-length path must be the load-controlled path, point
// by point, with the load factor increasing all the way (no doubling back).
TEST(ArcLength, ReproducesLoadControlOnTheSze31Strip) {
  const ShellModel model = sze31_model();
  StaticSolver path(model), reference(model);
  ArcLengthOptions options;
  options.initial_load_increment = 0.05;
  double previous = 0.0, worst_difference = 0.0, worst_residual = 0.0;
  int points = 0;
  path.run_arc_length(60, options, [&](const LoadStep& step) {
    EXPECT_GT(step.load_factor, previous) << "point " << points;
    previous = step.load_factor;
    reference.run(1, step.load_factor);
    const double difference = relative_difference(path.displacement(), reference.displacement());
    worst_difference = std::max(worst_difference, difference);
    worst_residual = std::max(worst_residual, path.relative_residual());
    EXPECT_LT(difference, 1e-6) << "load factor " << step.load_factor;
    ++points;
    return step.load_factor < 1.0;
  });
  std::printf(
      "Sze 3.1 arc length: %d points to load factor %.4f; worst relative difference to load control %.2e, "
      "worst relative residual %.2e\n",
      points, previous, worst_difference, worst_residual);
  EXPECT_GE(previous, 1.0);
  EXPECT_LT(worst_residual, 1e-6);
}

TEST(DisplacementControl, ReproducesLoadControlOnTheSze31Strip) {
  const ShellModel model = sze31_model();
  StaticSolver path(model), reference(model);
  const ControlledDisplacement tip{-1, "tip", 2};
  double worst_difference = 0.0;
  int points = 0;
  path.run_displacement_control(tip, 10, 6.6996, [&](const LoadStep& step) {
    reference.run(1, step.load_factor);
    const double difference = relative_difference(path.displacement(), reference.displacement());
    worst_difference = std::max(worst_difference, difference);
    EXPECT_LT(difference, 1e-6) << "load factor " << step.load_factor;
    EXPECT_LT(path.relative_residual(), 1e-6);
    ++points;
  });
  EXPECT_EQ(points, 10);
  EXPECT_NEAR(path.controlled_displacement(tip), 6.6996, 1e-12);
  // W = 6.6996 is the elastica's tip deflection at P_max (shell-references.md 3.1, 0.2 %).
  std::printf(
      "Sze 3.1 displacement control: load factor %.5f at W = 6.6996 (elastica 1); worst relative "
      "difference to load control %.2e\n",
      path.load_factor(), worst_difference);
  EXPECT_NEAR(path.load_factor(), 1.0, 2e-3);
  EXPECT_LT(worst_difference, 1e-6);
}

TEST(DisplacementControl, RejectsBadControlsAndOptions) {
  const ShellModel model = sze31_model();
  StaticSolver solver(model);
  EXPECT_THROW(solver.controlled_displacement({-1, "tip", 3}), InputError);
  EXPECT_THROW(solver.controlled_displacement({model.num_nodes(), "", 2}), InputError);
  EXPECT_THROW(solver.controlled_displacement({-1, "clamped", 2}), InputError);  // fixed by the support
  EXPECT_THROW(solver.controlled_displacement({-1, "no_such_group", 2}), InputError);
  EXPECT_THROW(solver.set_state(Eigen::VectorXd::Zero(3), 0.0), InputError);
  ArcLengthOptions no_increment;
  no_increment.initial_load_increment = 0.0;
  EXPECT_THROW(solver.run_arc_length(1, no_increment), InputError);
}

// Hinged cylindrical roof (Sze, Liu & Lo 2004): R = 2540, length 508, half-angle 0.1 rad,
// E = 3102.75, ν = 0.3, straight edges hinged, curved edges free, point load P = 1000 λ
// at the centre (quarter model: P / 4 at the corner node).
struct Roof {
  ShellModel model;
  Index centre = -1;
};

Roof hinged_roof(int n, double thickness) {
  ShellSection section;
  section.thickness = thickness;
  section.material = {3102.75, 0.3, 0.0};
  Roof roof{ShellModel(cubic_mesh("roof_hinged_" + std::to_string(n) + "x" + std::to_string(n) + ".geo"), section)};
  roof.model.add_support(Support::symmetry_plane("sym_x", 0));
  roof.model.add_support(Support::symmetry_plane("sym_y", 1));
  roof.model.add_support(Support::simply_supported("hinged"));
  double best = std::numeric_limits<double>::infinity();
  for (Index k = 0; k < roof.model.num_nodes(); ++k) {
    const double d = (roof.model.mesh().nodes[static_cast<std::size_t>(k)] - Vec3(0.0, 0.0, 2540.0)).norm();
    if (d < best) best = d, roof.centre = k;
  }
  EXPECT_LT(best, 1e-9);
  roof.model.add_point_load({roof.centre, Vec3(0.0, 0.0, -250.0)});
  return roof;
}

/// Load factor at the first limit point of a path of (deflection, load factor) points,
/// refined by the parabola through the first discrete maximum and its neighbours.
double limit_load(const std::vector<std::pair<double, double>>& path) {
  std::size_t k = 0;
  while (k + 1 < path.size() && path[k + 1].second > path[k].second) ++k;
  if (k == 0 || k + 1 >= path.size()) return path[k].second;
  const auto [x0, y0] = path[k - 1];
  const auto [x1, y1] = path[k];
  const auto [x2, y2] = path[k + 1];
  // Newton's divided differences; the vertex of the parabola.
  const double d01 = (y1 - y0) / (x1 - x0), d12 = (y2 - y1) / (x2 - x1), d012 = (d12 - d01) / (x2 - x0);
  const double x_vertex = 0.5 * (x0 + x1) - d01 / (2.0 * d012);
  return y0 + d01 * (x_vertex - x0) + d012 * (x_vertex - x0) * (x_vertex - x1);
}

/// Checks the path's shape: the load factor rises to a maximum, falls to a minimum below it
/// and rises again above that minimum.
void expect_snap_through(const std::vector<std::pair<double, double>>& path, const std::string& what) {
  std::size_t k_max = 0;
  while (k_max + 1 < path.size() && path[k_max + 1].second > path[k_max].second) ++k_max;
  std::size_t k_min = k_max;
  while (k_min + 1 < path.size() && path[k_min + 1].second < path[k_min].second) ++k_min;
  EXPECT_GT(k_max, 0u) << what << ": the load never rises";
  EXPECT_GT(k_min, k_max) << what << ": the load never falls after the limit point";
  EXPECT_LT(k_min + 1, path.size()) << what << ": the load never rises again";
  EXPECT_GT(path.back().second, path[k_min].second + 0.05 * (path[k_max].second - path[k_min].second)) << what;
  std::printf("%s: limit point at w = %.3f, load factor %.5f; minimum at w = %.3f, load factor %.5f; %zu points\n",
              what.c_str(), path[k_max].first, path[k_max].second, path[k_min].first, path[k_min].second, path.size());
}

TEST(ArcLength, HingedRoofSnapsThroughInEquilibrium) {
  Roof roof = hinged_roof(4, 12.7);
  StaticSolver solver(roof.model);
  const ControlledDisplacement centre{roof.centre, "", 2};
  ArcLengthOptions options;
  options.initial_load_increment = 0.2;
  std::vector<std::pair<double, double>> path{{0.0, 0.0}};
  double worst_residual = 0.0;
  int iterations = 0;
  solver.run_arc_length(200, options, [&](const LoadStep& step) {
    const double residual = solver.relative_residual();
    worst_residual = std::max(worst_residual, residual);
    EXPECT_LT(residual, 1e-6) << "load factor " << step.load_factor;
    path.emplace_back(-solver.controlled_displacement(centre), step.load_factor);
    iterations += step.iterations;
    return path.back().first < 30.0;
  });
  std::printf("roof h = 12.7, 4x4, arc length: %d Newton iterations, worst relative residual %.2e\n", iterations,
              worst_residual);
  expect_snap_through(path, "roof h = 12.7, 4x4, arc length");
  EXPECT_GE(path.back().first, 30.0);

  // The same path by displacement control of the centre at the arc-length points' deflections:
  // the load factors agree past the limit point too (one equilibrium per deflection here).
  StaticSolver control(roof.model);
  double worst_difference = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) {
    ASSERT_GT(control.solve_displacement(centre, -path[i].first), 0) << "w = " << path[i].first;
    worst_difference = std::max(worst_difference, std::abs(control.load_factor() - path[i].second));
  }
  std::printf("displacement control at the same deflections: worst |load factor difference| %.2e\n", worst_difference);
  EXPECT_LT(worst_difference, 1e-6);
}

// The thinner roof snaps back: past the limit point the centre deflection decreases along
// the path for a while, so displacement control of the centre cannot pass; arc length can.
TEST(ArcLength, ThinHingedRoofSnapsBack) {
  Roof roof = hinged_roof(4, 6.35);
  StaticSolver solver(roof.model);
  const ControlledDisplacement centre{roof.centre, "", 2};
  ArcLengthOptions options;
  options.initial_load_increment = 0.05;
  std::vector<std::pair<double, double>> path{{0.0, 0.0}};
  double worst_residual = 0.0, largest_w_before_turn = 0.0, smallest_w_after_turn = 0.0;
  bool turned_back = false;
  int iterations = 0;
  solver.run_arc_length(300, options, [&](const LoadStep& step) {
    const double residual = solver.relative_residual();
    worst_residual = std::max(worst_residual, residual);
    EXPECT_LT(residual, 1e-6) << "load factor " << step.load_factor;
    const double w = -solver.controlled_displacement(centre);
    if (!turned_back && w < path.back().first) {
      turned_back = true;
      largest_w_before_turn = smallest_w_after_turn = path.back().first;
    }
    if (turned_back) smallest_w_after_turn = std::min(smallest_w_after_turn, w);
    path.emplace_back(w, step.load_factor);
    iterations += step.iterations;
    return w < 25.0;
  });
  std::printf(
      "roof h = 6.35, 4x4, arc length: %d Newton iterations, worst relative residual %.2e; the centre "
      "deflection turns back from %.3f to %.3f\n",
      iterations, worst_residual, largest_w_before_turn, smallest_w_after_turn);
  expect_snap_through(path, "roof h = 6.35, 4x4, arc length");
  EXPECT_TRUE(turned_back);
  EXPECT_GT(largest_w_before_turn - smallest_w_after_turn, 0.5);
  EXPECT_GE(path.back().first, 25.0);
}

// Limit load of the h = 12.7 roof on 2x2, 4x4 and 8x8 quarter meshes (quads split into two
// cubic triangles), by displacement control of the centre in 1 mm steps to w = 13 (past the
// limit point near w = 10.5), refined by a parabola through the discrete maximum.
TEST(DisplacementControl, HingedRoofLimitLoadConverges) {
  std::printf("hinged roof h = 12.7, mesh (quarter)   limit load P = 1000 lambda\n");
  std::vector<double> limits;
  for (int n : {2, 4, 8}) {
    Roof roof = hinged_roof(n, 12.7);
    StaticSolver solver(roof.model);
    const ControlledDisplacement centre{roof.centre, "", 2};
    std::vector<std::pair<double, double>> path{{0.0, 0.0}};
    solver.run_displacement_control(centre, 13, -13.0, [&](const LoadStep& step) {
      EXPECT_LT(solver.relative_residual(), 1e-6);
      path.emplace_back(-solver.controlled_displacement(centre), step.load_factor);
    });
    EXPECT_LT(path.back().second, path[10].second) << "the path passes the limit point";
    limits.push_back(1000.0 * limit_load(path));
    std::printf("                 %dx%d                %.2f\n", n, n, limits.back());
  }
  // Converging: the change from 4x4 to 8x8 is well below the change from 2x2 to 4x4, and small.
  EXPECT_LT(std::abs(limits[2] - limits[1]), 0.5 * std::abs(limits[1] - limits[0]));
  EXPECT_LT(std::abs(limits[2] - limits[1]) / limits[2], 1e-3);
}

}  // namespace
}  // namespace shellflow::shell
