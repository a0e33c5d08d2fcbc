// Patch tests of shell.md §13.5. Membrane: a flat, distorted cubic mesh whose boundary nodes
// follow a linear displacement field (all G, a and interior positions free) takes the uniform
// Green–Lagrange strain of that field at every volume point. Bending: a strip with ν = 0
// under a small end couple bends with constant curvature M/EI (rotation linear in x).
// Also the linear Scordelis–Lo roof benchmark (shell-references.md, "Linear references")
// with its mesh-convergence table.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <numbers>
#include <random>

#include "reference_strip.h"
#include "shellflow/mesh/gmsh_io.h"
#include "shellflow/shell/linear_solver.h"
#include "shellflow/shell/static_solver.h"

namespace shellflow::shell {
namespace {

/// Distorts a flat cubic mesh: moves every element vertex that is not on one of
/// `fixed_groups` by a random offset of up to `amplitude` per component (x, and y when
/// `move_y`), puts the edge nodes back on the straight edges between the moved vertices,
/// and moves the face-centre nodes by up to `face_amplitude` (a curved isoparametric map
/// inside each element). The surface stays the plane z = 0.
void distort(mesh::Mesh& m, const std::vector<std::string>& fixed_groups, double amplitude, bool move_y,
             double face_amplitude) {
  std::vector<char> keep(m.nodes.size(), 0);
  for (const auto& name : fixed_groups)
    for (Index n : m.group(name).nodes) keep[static_cast<std::size_t>(n)] = 1;
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<char> moved(m.nodes.size(), 0);
  for (Index e = 0; e < m.cells.size(); ++e)
    for (int k = 0; k < 3; ++k) {
      const auto n = static_cast<std::size_t>(m.cells.element(e)[static_cast<std::size_t>(k)]);
      if (keep[n] || moved[n]) continue;
      moved[n] = 1;
      m.nodes[n].x() += amplitude * unit(rng);
      if (move_y) m.nodes[n].y() += amplitude * unit(rng);
    }
  for (Index e = 0; e < m.cells.size(); ++e) {
    const auto nodes = m.cells.element(e);
    const Vec3 v0 = m.nodes[static_cast<std::size_t>(nodes[0])], v1 = m.nodes[static_cast<std::size_t>(nodes[1])],
               v2 = m.nodes[static_cast<std::size_t>(nodes[2])];
    for (std::size_t j = 3; j < 10; ++j) {
      const auto& xi = fem::Tri10::node_points[j];
      Vec3& x = m.nodes[static_cast<std::size_t>(nodes[j])];
      if (keep[static_cast<std::size_t>(nodes[j])]) continue;  // boundary edge nodes stay
      x = (1.0 - xi[0] - xi[1]) * v0 + xi[0] * v1 + xi[1] * v2;
      if (j == 9) {
        x.x() += face_amplitude * unit(rng);
        if (move_y) x.y() += face_amplitude * unit(rng);
      }
    }
  }
}

/// Green–Lagrange strain at every volume point of every cell (default rule), by the
/// kernel's own kinematics.
std::vector<Mat3> strains_at_volume_points(const ShellModel& model, const Eigen::VectorXd& u) {
  using Tri = fem::Tri10;
  constexpr int N = Tri::num_nodes;
  const ShellQuadrature<Tri> rule(model.section().plane_degree, model.section().thickness_points);
  const auto& cells = model.mesh().cells;
  std::vector<Mat3> strains;
  for (Index e = 0; e < cells.size(); ++e) {
    const auto nodes = cells.element(e);
    typename ShellElementGeometry<Tri>::NodeVectors X, V;
    typename ShellElementGeometry<Tri>::NodeScalars h;
    Eigen::Matrix<double, dofs_per_node * N, 1> ue;
    for (int j = 0; j < N; ++j) {
      const Index n = nodes[static_cast<std::size_t>(j)];
      X.col(j) = model.mesh().nodes[static_cast<std::size_t>(n)];
      V.col(j) = model.directors()[static_cast<std::size_t>(n)];
      h(j) = model.section().thickness;
      ue.segment<dofs_per_node>(dofs_per_node * j) = u.segment<dofs_per_node>(dofs_per_node * n);
    }
    const ShellElementGeometry<Tri> geo(X, V, h, rule);
    detail::PlanePoint<N> p;
    for (int q = 0; q < rule.plane_size(); ++q) {
      p.interpolate(geo, rule.phi[static_cast<std::size_t>(q)], rule.dphi[static_cast<std::size_t>(q)], ue);
      for (int k = 0; k < rule.thickness_size(); ++k) {
        const auto ip = static_cast<std::size_t>(q * rule.thickness_size() + k);
        const Mat3 H = p.delta_A(rule.thickness_points[static_cast<std::size_t>(k)]) * geo.A0_inverse[ip];
        strains.push_back(detail::green_lagrange(H));
      }
    }
  }
  return strains;
}

TEST(ShellPatchTest, DistortedFlatMeshTakesTheImposedUniformMembraneStrainExactly) {
  mesh::Mesh m = cubic_mesh("patch_square.geo");
  ASSERT_EQ(m.cells.type, mesh::ElementType::tri10);
  distort(m, {"boundary"}, 0.08, true, 0.02);
  ShellSection section;
  section.thickness = 0.05;
  section.material = {1000.0, 0.3, 0.0};
  ShellModel model(std::move(m), section);  // throws if the distortion inverted an element
  Support boundary;
  boundary.group = "boundary";
  boundary.fix_position = {true, true, true};
  model.add_support(boundary);

  // Finite linear field x = F X (not small: the Green–Lagrange strain has its quadratic part).
  Mat3 F = Mat3::Identity();
  F.topLeftCorner<2, 2>() << 1.06, 0.03, -0.02, 1.04;  // stretched both ways (compression would buckle the plate)
  const Eigen::Matrix2d E_membrane =
      0.5 * (F.topLeftCorner<2, 2>().transpose() * F.topLeftCorner<2, 2>() - Eigen::Matrix2d::Identity());
  // Uniform plane stress (S33 = 0, no transverse shear): E33 = -λ/(λ + 2μ) (E11 + E22).
  const double lambda = section.material.lame_lambda(), mu = section.material.lame_mu();
  const double E33 = -lambda / (lambda + 2.0 * mu) * E_membrane.trace();

  // The boundary values are ramped in 4 steps (prescribed support displacements through
  // set_state): imposed at once, the elements along the boundary invert.
  StaticSolver solver(model);
  int iterations = 0;
  for (int step = 1; step <= 4; ++step) {
    Eigen::VectorXd u = solver.displacement();
    for (Index n : model.mesh().group("boundary").nodes) {
      const Vec3& X = model.mesh().nodes[static_cast<std::size_t>(n)];
      u.segment<3>(dofs_per_node * n) = 0.25 * step * (F - Mat3::Identity()) * X;
    }
    solver.set_state(u, 0.0);
    const int its = solver.solve(0.0);
    ASSERT_GT(its, 0) << "ramp step " << step;
    iterations += its;
  }

  double worst_membrane = 0.0, worst_shear = 0.0, worst_normal = 0.0;
  const std::vector<Mat3> strains = strains_at_volume_points(model, solver.displacement());
  for (const Mat3& E : strains) {
    worst_membrane = std::max(worst_membrane, (E.topLeftCorner<2, 2>() - E_membrane).cwiseAbs().maxCoeff());
    worst_shear = std::max({worst_shear, std::abs(E(0, 2)), std::abs(E(1, 2))});
    worst_normal = std::max(worst_normal, std::abs(E(2, 2) - E33));
  }
  // Interior nodes land on the linear field too.
  double worst_position = 0.0;
  for (Index n = 0; n < model.num_nodes(); ++n) {
    const Vec3& X = model.mesh().nodes[static_cast<std::size_t>(n)];
    worst_position = std::max(worst_position,
                              (node_position_increment(solver.displacement(), n) - (F - Mat3::Identity()) * X).norm());
  }
  std::printf(
      "membrane patch: %zu volume points, %d Newton iterations; worst |E_ab - imposed| %.2e, |E_a3| %.2e, "
      "|E33 - plane stress| %.2e, node position error %.2e\n",
      strains.size(), iterations, worst_membrane, worst_shear, worst_normal, worst_position);
  EXPECT_LT(worst_membrane, 1e-10);
  EXPECT_LT(worst_shear, 1e-10);
  EXPECT_LT(worst_normal, 1e-10);
  EXPECT_LT(worst_position, 1e-10);
}

// Sze 3.2 strip (L = 12, b = 1, h = 0.1, EI = 100, ν = 0) with its interior nodes moved
// along x, clamped at x = 0, a small end couple M: rotation ψ(X) = M X / EI and deflection
// w(X) = M X² / (2 EI) at every node, i.e. constant curvature M / EI.
TEST(ShellPatchTest, PureBendingStripHasConstantCurvature) {
  mesh::Mesh m = cubic_mesh("sze32_cantilever_8x1.geo");
  // Straight-sided (affine) elements only: w = κX²/2 is in the span of the shape functions
  // only when the element map is affine (moving the face-centre node breaks it, 13 % at
  // 0.05).
  distort(m, {"clamped", "tip"}, 0.3, false, 0.0);
  ShellSection section;
  section.thickness = 0.1;
  section.material = {1.2e6, 0.0, 0.0};
  ShellModel model(std::move(m), section);
  model.add_support(Support::clamped("clamped"));
  const double M = 0.01, L = 12.0, EI = 100.0, curvature = M / EI;
  model.add_edge_couple({"tip", -Vec3::UnitY(), M});
  StaticSolver solver(model);
  solver.run(1, 1.0);

  double worst_rotation = 0.0, worst_deflection = 0.0, tip_rotation = 0.0;
  for (Index n = 0; n < model.num_nodes(); ++n) {
    const double X = model.mesh().nodes[static_cast<std::size_t>(n)].x();
    const Vec3 G = model.directors()[static_cast<std::size_t>(n)] + node_director_increment(solver.displacement(), n);
    const double psi = std::atan2(-G.x(), G.z());
    const double w = node_position_increment(solver.displacement(), n).z();
    worst_rotation = std::max(worst_rotation, std::abs(psi - curvature * X));
    worst_deflection = std::max(worst_deflection, std::abs(w - 0.5 * curvature * X * X));
    if (X == L) tip_rotation = psi;
  }
  std::printf(
      "bending patch: tip rotation / (ML/EI) = %.9f; worst |psi - M X/EI| = %.2e (of ML/EI %.2e), "
      "worst |w - M X^2/(2EI)| = %.2e (of tip %.2e)\n",
      tip_rotation / (curvature * L), worst_rotation, curvature * L, worst_deflection, 0.5 * curvature * L * L);
  EXPECT_NEAR(tip_rotation / (curvature * L), 1.0, 1e-6);
  EXPECT_LT(worst_rotation, 1e-6 * curvature * L);
  EXPECT_LT(worst_deflection, 1e-5 * 0.5 * curvature * L * L);
}

// Scordelis–Lo roof: R = 25, length 50, half-angle 40°, h = 0.25, E = 4.32e8, ν = 0, gravity
// 90 per unit area (ρ h g = 360 · 0.25 · 1), rigid end diaphragms (y, z fixed, axial x and
// the director free), straight edges free; quarter model with symmetry planes. Reference:
// vertical deflection 0.3024 at the mid-point of the free edge. The linear solution is one
// Newton step from the unloaded state, K(0) u = F.
struct ScordelisLoResult {
  double linear = 0.0;     ///< -w at the free-edge mid-point, linear solve
  double nonlinear = 0.0;  ///< the same from Newton at load factor 1e-4, scaled back
};

ScordelisLoResult scordelis_lo(int n) {
  ShellSection section;
  section.thickness = 0.25;
  section.material = {4.32e8, 0.0, 360.0};
  ShellModel model(cubic_mesh("scordelis_lo_" + std::to_string(n) + "x" + std::to_string(n) + ".geo"), section);
  Support diaphragm;
  diaphragm.group = "diaphragm";
  diaphragm.fix_position = {false, true, true};
  model.add_support(diaphragm);
  model.add_support(Support::symmetry_plane("sym_x", 0));
  model.add_support(Support::symmetry_plane("sym_y", 1));
  model.add_gravity(Vec3(0.0, 0.0, -1.0));
  const double angle = 40.0 * std::numbers::pi / 180.0;
  const Vec3 point(25.0, 25.0 * std::sin(angle), 25.0 * std::cos(angle));
  Index node = -1;
  double best = std::numeric_limits<double>::infinity();
  for (Index k = 0; k < model.num_nodes(); ++k) {
    const double d = (model.mesh().nodes[static_cast<std::size_t>(k)] - point).norm();
    if (d < best) best = d, node = k;
  }
  EXPECT_LT(best, 1e-9);

  ScordelisLoResult result;
  SparseMatrix K = model.make_matrix();
  Eigen::VectorXd f_int;
  EXPECT_TRUE(model.assemble(Eigen::VectorXd::Zero(model.num_dofs()), f_int, &K));
  Eigen::VectorXd u = model.reference_load();
  NewtonLinearSolver linear;
  EXPECT_TRUE(linear.solve(K, model.constrained(), u, true));
  result.linear = -u(dofs_per_node * node + 2);

  if (n <= 8) {  // (the finest mesh only for the linear solve, to keep the test short)
    const double scale = 1e-4;
    StaticSolver solver(model);
    solver.run(1, scale);
    result.nonlinear = -solver.displacement()(dofs_per_node * node + 2) / scale;
  }
  return result;
}

TEST(ScordelisLoRoof, MeshConvergesToTheReferenceDeflection) {
  constexpr double reference = 0.3024;
  std::printf(
      "Scordelis-Lo quarter mesh (quads -> 2 cubic triangles)   -w linear   error     -w (Newton, 1e-4 load)\n");
  double previous_error = std::numeric_limits<double>::infinity();
  double finest_error = 0.0;
  for (int n : {2, 4, 8, 16}) {
    const ScordelisLoResult r = scordelis_lo(n);
    const double error = r.linear / reference - 1.0;
    char nonlinear[32] = "-";
    if (n <= 8) std::snprintf(nonlinear, sizeof nonlinear, "%.5f", r.nonlinear);
    std::printf("%2dx%-2d (%3d triangles)                                   %.5f    %+.3f %%  %s\n", n, n, 2 * n * n,
                r.linear, 100.0 * error, nonlinear);
    // Newton at a tiny load is the linear solution up to the O(load) nonlinearity.
    if (n <= 8) {
      EXPECT_NEAR(r.nonlinear / r.linear, 1.0, 1e-3) << n << "x" << n;
    }
    if (n >= 4) {
      EXPECT_LT(std::abs(error), std::abs(previous_error)) << n << "x" << n;
    }
    previous_error = error;
    finest_error = error;
  }
  EXPECT_LT(std::abs(finest_error), 1e-2);
}

}  // namespace
}  // namespace shellflow::shell
