// The linear solves of the shell Newton iterations (shell/linear_solver.h): the reduced,
// node-ordered LDLT of NewtonLinearSolver against a dense solve of the free-dof system, the
// factorise-once / solve-many split, the LU path, new constraints, and ShellSystemSolver's
// local frames against an explicit dense basis change.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cstdio>

#include "shellflow/shell/linear_solver.h"
#include "structured_shell_mesh.h"

namespace shellflow::shell {
namespace {

ShellModel small_strip(const Mat3& R = Mat3::Identity()) {
  ShellSection section;
  section.thickness = 0.02;
  section.material = {2e9, 0.3, 0.0};
  return ShellModel(testing::structured_shell_mesh(
                        1.0, 0.2, 3, 1, [&](double s, double t) { return Vec3(R * Vec3(s, t, 0.1 * s * s)); }),
                    section);
}

/// A tangent at a deformed state (not just the initial stiffness).
SparseMatrix tangent(const ShellModel& model) {
  Eigen::VectorXd u = Eigen::VectorXd::Zero(model.num_dofs()), f;
  for (Index n = 0; n < model.num_nodes(); ++n)
    u(7 * n + 2) = 0.01 * model.mesh().nodes[static_cast<std::size_t>(n)].x();
  SparseMatrix K = model.make_matrix();
  EXPECT_TRUE(model.assemble(u, f, &K));
  return K;
}

/// Dense solution of K x = b on the free dofs (x = 0 on the fixed ones).
Eigen::VectorXd dense_reduced_solve(const SparseMatrix& K, const std::vector<char>& fixed, const Eigen::VectorXd& b) {
  std::vector<Eigen::Index> free;
  for (Eigen::Index i = 0; i < K.rows(); ++i)
    if (!fixed[static_cast<std::size_t>(i)]) free.push_back(i);
  const Eigen::MatrixXd dense(K);
  Eigen::MatrixXd A(free.size(), free.size());
  Eigen::VectorXd rhs(free.size());
  for (std::size_t i = 0; i < free.size(); ++i) {
    rhs(static_cast<Eigen::Index>(i)) = b(free[i]);
    for (std::size_t j = 0; j < free.size(); ++j)
      A(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = dense(free[i], free[j]);
  }
  const Eigen::VectorXd y = A.fullPivLu().solve(rhs);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(b.size());
  for (std::size_t i = 0; i < free.size(); ++i) x(free[i]) = y(static_cast<Eigen::Index>(i));
  return x;
}

TEST(NewtonLinearSolver, ReducedLdltMatchesADenseSolveOfTheFreeDofs) {
  ShellModel model = small_strip();
  model.add_support(Support::clamped("left"));
  const SparseMatrix K0 = tangent(model);
  const Eigen::VectorXd b = Eigen::VectorXd::Random(model.num_dofs());
  const Eigen::VectorXd expected = dense_reduced_solve(K0, model.constrained(), b);
  NewtonLinearSolver solver;
  SparseMatrix K = K0;
  Eigen::VectorXd x = b;
  ASSERT_TRUE(solver.solve(K, model.constrained(), x));
  const double error = (x - expected).norm() / expected.norm();
  std::printf("reduced LDLT vs dense: rel. difference %.2e\n", error);
  EXPECT_LT(error, 1e-9);
  for (std::size_t i = 0; i < model.constrained().size(); ++i)
    if (model.constrained()[i]) {
      EXPECT_EQ(x(static_cast<Eigen::Index>(i)), 0.0);
    }

  // One factorisation, two right-hand sides = two full solves.
  SparseMatrix K2 = K0;
  ASSERT_TRUE(solver.factorize(K2, model.constrained()));
  Eigen::VectorXd x1 = b, x2 = 2.0 * b;
  ASSERT_TRUE(solver.solve(x1));
  ASSERT_TRUE(solver.solve(x2));
  EXPECT_LT((x1 - x).norm(), 1e-12 * x.norm());
  EXPECT_LT((x2 - 2.0 * x).norm(), 1e-12 * x.norm());

  // The LU path (non-symmetric tangents) gives the same solution.
  SparseMatrix K3 = K0;
  Eigen::VectorXd x3 = b;
  NewtonLinearSolver lu;
  ASSERT_TRUE(lu.solve(K3, model.constrained(), x3, false));
  EXPECT_LT((x3 - expected).norm(), 1e-9 * expected.norm());
}

TEST(NewtonLinearSolver, ReducedLuOfANonSymmetricTangentMatchesADenseSolve) {
  ShellModel model = small_strip();
  model.add_support(Support::clamped("left"));
  model.add_follower_pressure({"", 5e4});
  SparseMatrix K0 = tangent(model);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(model.num_dofs()), f = u;
  for (Index n = 0; n < model.num_nodes(); ++n)
    u(7 * n + 2) = 0.01 * model.mesh().nodes[static_cast<std::size_t>(n)].x();
  model.add_follower_loads(u, 1.0, 0.0, f, &K0);
  const Eigen::MatrixXd dense(K0);
  ASSERT_GT((dense - dense.transpose()).norm(), 1e-6 * dense.norm());  // really non-symmetric
  const Eigen::VectorXd b = Eigen::VectorXd::Random(model.num_dofs());
  const Eigen::VectorXd expected = dense_reduced_solve(K0, model.constrained(), b);
  NewtonLinearSolver solver;
  for (int round = 0; round < 2; ++round) {  // analysed once, factorised twice
    SparseMatrix K = K0;
    Eigen::VectorXd x = b;
    ASSERT_TRUE(solver.solve(K, model.constrained(), x, false));
    EXPECT_LT((x - expected).norm(), 1e-9 * expected.norm());
    for (std::size_t i = 0; i < model.constrained().size(); ++i)
      if (model.constrained()[i]) {
        EXPECT_EQ(x(static_cast<Eigen::Index>(i)), 0.0);
      }
  }
  // The same solver switches back to the symmetric path (symmetric K: LDLT).
  SparseMatrix K = tangent(model);
  const Eigen::VectorXd expected_symmetric = dense_reduced_solve(K, model.constrained(), b);
  Eigen::VectorXd x = b;
  ASSERT_TRUE(solver.solve(K, model.constrained(), x, true));
  EXPECT_LT((x - expected_symmetric).norm(), 1e-9 * expected_symmetric.norm());
}

TEST(NewtonLinearSolver, NewConstraintsAreAnalysedAgain) {
  ShellModel model = small_strip();
  model.add_support(Support::clamped("left"));
  const SparseMatrix K0 = tangent(model);
  const Eigen::VectorXd b = Eigen::VectorXd::Random(model.num_dofs());
  NewtonLinearSolver solver;
  SparseMatrix K = K0;
  Eigen::VectorXd x = b;
  ASSERT_TRUE(solver.solve(K, model.constrained(), x));
  std::vector<char> more = model.constrained();
  for (Index n : model.mesh().group("right").nodes) more[static_cast<std::size_t>(7 * n + 2)] = 1;
  K = K0;
  x = b;
  ASSERT_TRUE(solver.solve(K, more, x));
  const Eigen::VectorXd expected = dense_reduced_solve(K0, more, b);
  EXPECT_LT((x - expected).norm(), 1e-9 * expected.norm());
}

TEST(ShellSystemSolver, LocalFramesSolveTheRotatedSystem) {
  // Supports along non-axis directions: the correction must satisfy T^T K T y = T^T b on
  // the free local components, with x = T y.
  const Mat3 Q = Eigen::AngleAxisd(0.7, Vec3(1.0, 2.0, -0.5).normalized()).toRotationMatrix();
  ShellModel model = small_strip(Q);
  model.add_support(Support::clamped("left"));
  model.add_support(DirectionalSupport::roller("right", Q * Vec3(1.0, 0.3, 0.0), false));
  model.add_support(DirectionalSupport::symmetry_plane("bottom", Q * Vec3::UnitY()));
  ASSERT_TRUE(model.has_local_frames());
  const SparseMatrix K0 = tangent(model);
  const Eigen::VectorXd b = Eigen::VectorXd::Random(model.num_dofs());
  // Dense T from to_global on unit vectors.
  const Eigen::Index n = model.num_dofs();
  Eigen::MatrixXd T(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    Eigen::VectorXd e = Eigen::VectorXd::Unit(n, j);
    model.to_global(e);
    T.col(j) = e;
  }
  const Eigen::MatrixXd K_local = T.transpose() * Eigen::MatrixXd(K0) * T;
  const Eigen::VectorXd y = dense_reduced_solve(K_local.sparseView(), model.constrained(), T.transpose() * b);
  const Eigen::VectorXd expected = T * y;
  ShellSystemSolver solver(model);
  SparseMatrix K = K0;
  Eigen::VectorXd x = b;
  ASSERT_TRUE(solver.solve(K, x));
  const double error = (x - expected).norm() / expected.norm();
  std::printf("local frames vs dense T^T K T: rel. difference %.2e\n", error);
  EXPECT_LT(error, 1e-9);
  // The correction has no component along any fixed direction.
  Eigen::VectorXd free_part = x;
  model.remove_fixed_part(free_part);
  EXPECT_LT((free_part - x).norm(), 1e-12 * x.norm());
}

}  // namespace
}  // namespace shellflow::shell
