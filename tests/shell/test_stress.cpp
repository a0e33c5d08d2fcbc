// Stress recovery (shell.md §2.5, §3): uniaxial stretch of a flat plate against the exact
// SVK solution, pure bending of a plate strip by an end couple (σ = ±6m/h²), zero stress
// under rigid motion, objectivity of the Cauchy stress.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "shellflow/core/error.h"
#include "shellflow/shell/shell_stress.h"
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

ShellModel flat_plate(int nx, int ny) {
  return ShellModel(
      testing::structured_shell_mesh(1.0, 0.5, nx, ny, [](double s, double t) { return Vec3(s, t, 0.0); }), section());
}

/// Stretch of a plate by a dead line load q per reference length along x on its right
/// edge, with symmetry planes on the left and bottom edges and z held: uniaxial stress.
struct StretchedPlate {
  ShellModel model = flat_plate(4, 2);
  Eigen::VectorXd u;
  double q = 1e5;
  StretchedPlate() {
    model.add_support(Support::symmetry_plane("left", 0));
    model.add_support(Support::symmetry_plane("bottom", 1));
    model.add_support({"shell", {false, false, true}, {}, false});
    model.add_line_load({"right", Vec3(q, 0.0, 0.0)});
    StaticSolver solver(model);
    solver.run(2, 1.0);
    u = solver.displacement();
  }
};

TEST(ShellStress, UniaxialStretchMatchesTheExactSvkSolution) {
  const StretchedPlate plate;
  // First Piola–Kirchhoff P_xx = λ1 S_xx = q / h with S_xx = E (λ1² − 1)/2 (uniaxial SVK).
  double l1 = 1.0;
  for (int it = 0; it < 50; ++it) {
    const double r = l1 * young * 0.5 * (l1 * l1 - 1.0) - plate.q / thickness;
    l1 -= r / (young * 0.5 * (3.0 * l1 * l1 - 1.0));
  }
  const double Exx = 0.5 * (l1 * l1 - 1.0);
  const double Sxx = young * Exx;
  const double l2 = std::sqrt(1.0 - 2.0 * poisson * Exx);  // λ2 = λ3
  const double sigma_xx = l1 * l1 * Sxx / (l1 * l2 * l2);
  std::printf("stretch: lambda1 %.9f, S_xx %.6e, sigma_xx %.6e\n", l1, Sxx, sigma_xx);
  double worst_S = 0.0, worst_sigma = 0.0, worst_zero = 0.0;
  for (SurfaceSide side : {SurfaceSide::bottom, SurfaceSide::middle, SurfaceSide::top}) {
    const NodalStresses S = nodal_stresses(plate.model, plate.u, StressMeasure::second_piola_kirchhoff, side);
    const NodalStresses sigma = nodal_stresses(plate.model, plate.u, StressMeasure::cauchy, side);
    const NodalStresses E = nodal_stresses(plate.model, plate.u, StressMeasure::green_lagrange_strain, side);
    for (std::size_t n = 0; n < S.tensor.size(); ++n) {
      worst_S = std::max(worst_S, std::abs(S.tensor[n](0, 0) / Sxx - 1.0));
      worst_sigma = std::max(worst_sigma, std::abs(sigma.tensor[n](0, 0) / sigma_xx - 1.0));
      Mat3 rest = S.tensor[n];
      rest(0, 0) = 0.0;
      worst_zero = std::max(worst_zero, rest.cwiseAbs().maxCoeff() / Sxx);
      EXPECT_NEAR(E.tensor[n](1, 1), -poisson * Exx, 1e-9);
      EXPECT_NEAR(E.tensor[n](2, 2), -poisson * Exx, 1e-9);
      EXPECT_NEAR(S.von_mises[n] / Sxx, 1.0, 1e-7);
    }
  }
  std::printf("stretch: max rel. error S_xx %.2e, sigma_xx %.2e; other S components / S_xx %.2e\n", worst_S,
              worst_sigma, worst_zero);
  EXPECT_LT(worst_S, 1e-7);
  EXPECT_LT(worst_sigma, 1e-7);
  EXPECT_LT(worst_zero, 1e-7);  // includes S_zz ≈ 0: plane stress reached through G and a
}

TEST(ShellStress, EndCoupleGivesTheBeamBendingStress) {
  // Plate strip 1 x 0.1 clamped at the left, symmetry planes on the long edges (cylindrical
  // bending), couple m per length about +y at the right: σ_xx = ±6 m / h² at top/bottom.
  ShellModel model(testing::structured_shell_mesh(1.0, 0.1, 8, 1, [](double s, double t) { return Vec3(s, t, 0.0); }),
                   section());
  model.add_support(Support::clamped("left"));
  model.add_support(Support::symmetry_plane("bottom", 1));
  model.add_support(Support::symmetry_plane("top", 1));
  const double D = young * thickness * thickness * thickness / (12.0 * (1.0 - poisson * poisson));
  const double m = 1e-4 * D;  // tip rotation 1e-4 rad: linear regime
  model.add_edge_couple({"right", Vec3::UnitY(), m});
  StaticSolver solver(model);
  solver.run(1, 1.0);
  const double sigma_ref = 6.0 * m / (thickness * thickness);
  const NodalStresses top = nodal_stresses(model, solver.displacement(), StressMeasure::cauchy, SurfaceSide::top);
  const NodalStresses bottom = nodal_stresses(model, solver.displacement(), StressMeasure::cauchy, SurfaceSide::bottom);
  const NodalStresses mid = nodal_stresses(model, solver.displacement(), StressMeasure::cauchy, SurfaceSide::middle);
  double worst = 0.0, worst_mid = 0.0, worst_yy = 0.0;
  int checked = 0;
  for (Index n = 0; n < model.num_nodes(); ++n) {
    const double x = model.mesh().nodes[static_cast<std::size_t>(n)].x();
    if (x < 0.25 || x > 0.75) continue;  // away from the clamp's boundary layer
    const auto k = static_cast<std::size_t>(n);
    worst = std::max(
        {worst, std::abs(top.tensor[k](0, 0) / sigma_ref - 1.0), std::abs(bottom.tensor[k](0, 0) / sigma_ref + 1.0)});
    worst_mid = std::max(worst_mid, mid.tensor[k].cwiseAbs().maxCoeff() / sigma_ref);
    worst_yy = std::max(worst_yy, std::abs(top.tensor[k](1, 1) / (poisson * sigma_ref) - 1.0));
    ++checked;
  }
  std::printf(
      "bending: sigma_ref %.6e, max rel. error top/bottom %.2e, |mid| / sigma_ref %.2e, sigma_yy/(nu sigma) %.2e (%d "
      "nodes)\n",
      sigma_ref, worst, worst_mid, worst_yy, checked);
  EXPECT_GT(checked, 10);
  EXPECT_LT(worst, 1e-5);
  EXPECT_LT(worst_mid, 1e-5);
  EXPECT_LT(worst_yy, 1e-5);  // plane strain across the strip: σ_yy = ν σ_xx
}

TEST(ShellStress, RigidMotionGivesNoStrainOrStress) {
  // A curved shell (quarter cylinder), rotated and translated as a whole.
  const ShellModel model(testing::structured_shell_mesh(
                             1.0, 1.5, 3, 3, [](double s, double t) { return Vec3(s, std::sin(t), std::cos(t)); }),
                         section());
  const Mat3 R = Eigen::AngleAxisd(1.3, Vec3(1, -2, 0.5).normalized()).toRotationMatrix();
  Eigen::VectorXd u = Eigen::VectorXd::Zero(model.num_dofs());
  for (Index n = 0; n < model.num_nodes(); ++n) {
    const Vec3& X = model.mesh().nodes[static_cast<std::size_t>(n)];
    const Vec3& V = model.directors()[static_cast<std::size_t>(n)];
    u.segment<3>(7 * n) = R * X + Vec3(0.3, -0.2, 1.0) - X;
    u.segment<3>(7 * n + 3) = R * V - V;
  }
  double worst = 0.0;
  for (SurfaceSide side : {SurfaceSide::bottom, SurfaceSide::middle, SurfaceSide::top})
    for (StressMeasure measure : {StressMeasure::second_piola_kirchhoff, StressMeasure::cauchy}) {
      const NodalStresses s = nodal_stresses(model, u, measure, side);
      for (double v : s.von_mises) worst = std::max(worst, v / young);
    }
  const StressPoint p = stress_at(model, u, {4, Vec2(0.2, 0.3)}, 0.5);
  std::printf("rigid motion: max von Mises / E %.2e; |E| at a point %.2e\n", worst, p.E.norm());
  EXPECT_LT(worst, 1e-13);
  EXPECT_LT(p.E.norm(), 1e-13);
  EXPECT_NEAR((p.F - R).norm(), 0.0, 1e-13);
}

TEST(ShellStress, CauchyStressRotatesWithASuperposedRotation) {
  const StretchedPlate plate;
  const ShellModel& model = plate.model;
  // Superpose a rigid rotation R on the stretched state: S is unchanged, σ' = R σ Rᵀ.
  const Mat3 R = Eigen::AngleAxisd(0.9, Vec3(0.3, 1.0, -0.4).normalized()).toRotationMatrix();
  Eigen::VectorXd rotated = plate.u;
  for (Index n = 0; n < model.num_nodes(); ++n) {
    const Vec3& X = model.mesh().nodes[static_cast<std::size_t>(n)];
    const Vec3& V = model.directors()[static_cast<std::size_t>(n)];
    rotated.segment<3>(7 * n) = R * (X + plate.u.segment<3>(7 * n)) - X;
    rotated.segment<3>(7 * n + 3) = R * (V + plate.u.segment<3>(7 * n + 3)) - V;
  }
  for (const ShellPoint& p : {ShellPoint{0, Vec2(0.1, 0.2)}, ShellPoint{9, Vec2(0.6, 0.3)}})
    for (double xi3 : {-1.0, 0.3, 1.0}) {
      const StressPoint a = stress_at(model, plate.u, p, xi3);
      const StressPoint b = stress_at(model, rotated, p, xi3);
      const double scale = a.sigma.norm();
      EXPECT_LT((b.S - a.S).norm() / scale, 1e-12);
      EXPECT_LT((b.sigma - R * a.sigma * R.transpose()).norm() / scale, 1e-12);
      EXPECT_NEAR(von_mises(b.sigma), von_mises(a.sigma), 1e-12 * scale);
      EXPECT_LT((b.F - R * a.F).norm(), 1e-12);
    }
}

TEST(ShellStress, VonMisesOfKnownTensors) {
  Mat3 uniaxial = Mat3::Zero();
  uniaxial(0, 0) = 5.0;
  EXPECT_NEAR(von_mises(uniaxial), 5.0, 1e-14);
  Mat3 shear = Mat3::Zero();
  shear(0, 1) = shear(1, 0) = 2.0;
  EXPECT_NEAR(von_mises(shear), 2.0 * std::sqrt(3.0), 1e-14);
  EXPECT_NEAR(von_mises(7.0 * Mat3::Identity()), 0.0, 1e-14);
}

TEST(ShellStress, BadInputStopsWithAMessage) {
  const ShellModel model = flat_plate(1, 1);
  const Eigen::VectorXd u = Eigen::VectorXd::Zero(model.num_dofs());
  EXPECT_THROW(stress_at(model, u, {2, Vec2::Zero()}, 0.0), InputError);
  EXPECT_THROW(stress_at(model, u, {0, Vec2::Zero()}, 1.5), InputError);
  Eigen::VectorXd crushed = u;
  for (Index n = 0; n < model.num_nodes(); ++n) crushed.segment<3>(7 * n + 3) = Vec3(0, 0, -2.0);  // G = -V
  EXPECT_THROW(stress_at(model, crushed, {0, Vec2(0.2, 0.2)}, 0.0), SolverError);
}

}  // namespace
}  // namespace shellflow::shell
