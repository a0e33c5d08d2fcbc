// Element kernel of the positional shell (shell.md §13 items 2, 3, 4, 7): strain-free and
// rigid states, derivatives against finite differences, mass totals.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>

#include "shellflow/shell/shell_element.h"

namespace shellflow::shell {
namespace {

constexpr double h0 = 0.1;

/// A curved element: the reference triangle scaled to ~1 and wrapped on a cylinder of
/// radius 2 about the y axis, nodes randomly perturbed; directors are the element's own
/// normals at the nodes (as shell.md §9 computes them for a single element).
template <class Tri>
ShellElementGeometry<Tri> curved_element(const ShellQuadrature<Tri>& rule, double perturbation) {
  constexpr int N = Tri::num_nodes;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> noise(-perturbation, perturbation);
  typename ShellElementGeometry<Tri>::NodeVectors X, V;
  const double R = 2.0;
  for (int j = 0; j < N; ++j) {
    const double s =
        1.1 * Tri::node_points[static_cast<std::size_t>(j)][0] + 0.2 * Tri::node_points[static_cast<std::size_t>(j)][1];
    const double y = 0.9 * Tri::node_points[static_cast<std::size_t>(j)][1];
    X.col(j) = Vec3(R * std::sin(s / R), y, R * std::cos(s / R)) + Vec3(noise(rng), noise(rng), noise(rng));
  }
  for (int j = 0; j < N; ++j) {
    double dN[2 * N];
    Tri::eval_gradients(Tri::node_points[static_cast<std::size_t>(j)].data(), dN);
    Vec3 t1 = Vec3::Zero(), t2 = Vec3::Zero();
    for (int k = 0; k < N; ++k) {
      t1 += dN[2 * k] * X.col(k);
      t2 += dN[2 * k + 1] * X.col(k);
    }
    V.col(j) = t1.cross(t2).normalized();
  }
  return ShellElementGeometry<Tri>(X, V, ShellElementGeometry<Tri>::NodeScalars::Constant(h0), rule);
}

SvkMaterial material() { return {1000.0, 0.3, 2.0}; }

Mat3 rotation_120_about_123() {
  return Eigen::AngleAxisd(2.0 * M_PI / 3.0, Vec3(1, 2, 3).normalized()).toRotationMatrix();
}

template <class Tri>
class ShellElementTest : public ::testing::Test {};
using TriangleTypes = ::testing::Types<fem::Tri3, fem::Tri6, fem::Tri10>;
TYPED_TEST_SUITE(ShellElementTest, TriangleTypes);

TYPED_TEST(ShellElementTest, InitialStateIsStrainFreeAndUnloaded) {
  using Tri = TypeParam;
  const ShellQuadrature<Tri> rule;
  const auto geo = curved_element<Tri>(rule, 0.05);
  ASSERT_GT(geo.min_J0, 0.0);
  constexpr int nd = ShellElementGeometry<Tri>::num_dofs;
  const Eigen::Matrix<double, nd, 1> u = Eigen::Matrix<double, nd, 1>::Zero();
  Eigen::Matrix<double, nd, 1> f;
  ASSERT_TRUE(internal_force(geo, rule, material(), u, f, nullptr));
  EXPECT_EQ(max_abs_strain(geo, rule, u), 0.0);
  EXPECT_EQ(f.norm(), 0.0);
}

TYPED_TEST(ShellElementTest, RigidRotationAndTranslationGiveZeroStrainAndForce) {
  using Tri = TypeParam;
  constexpr int N = Tri::num_nodes;
  constexpr int nd = ShellElementGeometry<Tri>::num_dofs;
  const ShellQuadrature<Tri> rule;
  const auto geo = curved_element<Tri>(rule, 0.05);
  const Mat3 R = rotation_120_about_123();
  const Vec3 c(0.3, -0.2, 0.5);
  Eigen::Matrix<double, nd, 1> u = Eigen::Matrix<double, nd, 1>::Zero();
  for (int j = 0; j < N; ++j) {
    u.template segment<3>(7 * j) = R * geo.X.col(j) + c - geo.X.col(j);
    u.template segment<3>(7 * j + 3) = R * geo.V.col(j) - geo.V.col(j);
  }
  Eigen::Matrix<double, nd, 1> f;
  Eigen::Matrix<double, nd, nd> K;
  ASSERT_TRUE(internal_force(geo, rule, material(), u, f, &K));
  EXPECT_LT(max_abs_strain(geo, rule, u), 1e-14);
  EXPECT_LT(strain_energy(geo, rule, material(), u), 1e-25);
  // Force scale: E h times an edge length ~ 100.
  EXPECT_LT(f.cwiseAbs().maxCoeff(), 1e-11);
  // A deformed-state check that the finite rotation is what makes E vanish.
  u(0) += 0.01;
  EXPECT_GT(max_abs_strain(geo, rule, u), 1e-4);
}

TYPED_TEST(ShellElementTest, FreeElementStiffnessHasSixRigidBodyModes) {
  using Tri = TypeParam;
  constexpr int nd = ShellElementGeometry<Tri>::num_dofs;
  const ShellQuadrature<Tri> rule;
  const auto geo = curved_element<Tri>(rule, 0.05);
  const Eigen::Matrix<double, nd, 1> u = Eigen::Matrix<double, nd, 1>::Zero();
  Eigen::Matrix<double, nd, 1> f;
  Eigen::Matrix<double, nd, nd> K;
  internal_force(geo, rule, material(), u, f, &K);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig{Eigen::MatrixXd(K)};
  const Eigen::VectorXd ev = eig.eigenvalues();
  const double scale = ev.cwiseAbs().maxCoeff();
  for (int i = 0; i < 6; ++i) EXPECT_LT(std::abs(ev(i)), 1e-10 * scale) << "eigenvalue " << i;
  EXPECT_GT(ev(6), 1e-9 * scale);
}

/// Random non-trivial state: moderate stretch, bending, director tilt and a.
template <class Tri>
Eigen::Matrix<double, ShellElementGeometry<Tri>::num_dofs, 1> random_state(unsigned seed) {
  constexpr int nd = ShellElementGeometry<Tri>::num_dofs;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  Eigen::Matrix<double, nd, 1> u;
  for (int r = 0; r < nd; ++r) {
    const int kind = r % 7;
    u(r) = (kind < 3 ? 0.05 : kind < 6 ? 0.1 : 0.05) * d(rng);
  }
  return u;
}

TYPED_TEST(ShellElementTest, InternalForceIsTheEnergyGradient) {
  using Tri = TypeParam;
  constexpr int nd = ShellElementGeometry<Tri>::num_dofs;
  const ShellQuadrature<Tri> rule;
  const auto geo = curved_element<Tri>(rule, 0.05);
  const auto u = random_state<Tri>(11);
  Eigen::Matrix<double, nd, 1> f;
  ASSERT_TRUE(internal_force(geo, rule, material(), u, f, nullptr));
  Eigen::Matrix<double, nd, 1> f_fd;
  const double step = 1e-5;
  for (int r = 0; r < nd; ++r) {
    auto up = u, um = u;
    up(r) += step;
    um(r) -= step;
    f_fd(r) = (strain_energy(geo, rule, material(), up) - strain_energy(geo, rule, material(), um)) / (2 * step);
  }
  EXPECT_LT((f - f_fd).norm() / f.norm(), 1e-6);
}

TYPED_TEST(ShellElementTest, TangentIsTheInternalForceDerivative) {
  using Tri = TypeParam;
  constexpr int nd = ShellElementGeometry<Tri>::num_dofs;
  const ShellQuadrature<Tri> rule;
  const auto geo = curved_element<Tri>(rule, 0.05);
  const auto u = random_state<Tri>(12);
  Eigen::Matrix<double, nd, 1> f;
  Eigen::Matrix<double, nd, nd> K, K_fd;
  ASSERT_TRUE(internal_force(geo, rule, material(), u, f, &K));
  const double step = 1e-6;
  for (int s = 0; s < nd; ++s) {
    auto up = u, um = u;
    up(s) += step;
    um(s) -= step;
    Eigen::Matrix<double, nd, 1> fp, fm;
    internal_force(geo, rule, material(), up, fp, nullptr);
    internal_force(geo, rule, material(), um, fm, nullptr);
    K_fd.col(s) = (fp - fm) / (2 * step);
  }
  EXPECT_LT((K - K_fd).norm() / K.norm(), 1e-6);
  EXPECT_LT((K - K.transpose()).norm() / K.norm(), 1e-13);
  // The a–G block alone (it is small next to the membrane terms, so check it separately).
  double err = 0.0, ref = 0.0;
  for (int r = 6; r < nd; r += 7)
    for (int s = 0; s < nd; ++s)
      if (s % 7 >= 3 && s % 7 < 6) {
        err += std::pow(K(r, s) - K_fd(r, s), 2);
        ref += std::pow(K(r, s), 2);
      }
  EXPECT_LT(std::sqrt(err / ref), 1e-6);
}

TYPED_TEST(ShellElementTest, MassOfFlatElementMatchesPlateValues) {
  using Tri = TypeParam;
  constexpr int N = Tri::num_nodes;
  constexpr int nd = ShellElementGeometry<Tri>::num_dofs;
  const ShellQuadrature<Tri> rule;
  // Flat straight-sided triangle (0,0) (2,0) (0.5,1.5) in z = 0: area 1.5.
  typename ShellElementGeometry<Tri>::NodeVectors X, V;
  for (int j = 0; j < N; ++j) {
    const double x1 = Tri::node_points[static_cast<std::size_t>(j)][0];
    const double x2 = Tri::node_points[static_cast<std::size_t>(j)][1];
    X.col(j) = Vec3(2.0 * x1 + 0.5 * x2, 1.5 * x2, 0.0);
    V.col(j) = Vec3::UnitZ();
  }
  const ShellElementGeometry<Tri> geo(X, V, ShellElementGeometry<Tri>::NodeScalars::Constant(h0), rule);
  const double rho = 2.0, area = 1.5;
  const Eigen::Matrix<double, nd, nd> M = mass_matrix(geo, rule, rho);
  double mxx = 0, mxg = 0, mgg = 0;
  for (int j = 0; j < N; ++j)
    for (int k = 0; k < N; ++k) {
      mxx += M(7 * j, 7 * k);
      mxg += M(7 * j, 7 * k + 3);
      mgg += M(7 * j + 3, 7 * k + 3);
    }
  EXPECT_NEAR(mxx, rho * h0 * area, 1e-13);
  EXPECT_NEAR(mxg, 0.0, 1e-15);
  EXPECT_NEAR(mgg, rho * h0 * h0 * h0 / 12.0 * area, 1e-15);
  EXPECT_EQ(M.row(6).norm(), 0.0);  // a carries no inertia (shell.md §6)
  EXPECT_LT((M - M.transpose()).norm(), 1e-15);
  // Kinetic energy of a rigid translation v: ½ m |v|².
  Eigen::Matrix<double, nd, 1> v = Eigen::Matrix<double, nd, 1>::Zero();
  for (int j = 0; j < N; ++j) v.template segment<3>(7 * j) = Vec3(1.0, -2.0, 0.5);
  EXPECT_NEAR(0.5 * v.dot(M * v), 0.5 * rho * h0 * area * 5.25, 1e-12);
}

TYPED_TEST(ShellElementTest, MassOfCurvedElementIsItsVolumeTimesDensity) {
  using Tri = TypeParam;
  constexpr int N = Tri::num_nodes;
  constexpr int nd = ShellElementGeometry<Tri>::num_dofs;
  const ShellQuadrature<Tri> rule;
  const auto geo = curved_element<Tri>(rule, 0.05);
  double volume = 0.0;
  for (double dv : geo.dV) volume += dv;
  const Eigen::Matrix<double, nd, nd> M = mass_matrix(geo, rule, 3.0);
  double mxx = 0.0;
  for (int j = 0; j < N; ++j)
    for (int k = 0; k < N; ++k) mxx += M(7 * j + 1, 7 * k + 1);
  EXPECT_NEAR(mxx, 3.0 * volume, 1e-13);
}

}  // namespace
}  // namespace shellflow::shell
