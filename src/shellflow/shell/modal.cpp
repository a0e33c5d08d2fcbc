#include "shellflow/shell/modal.h"

#include <cmath>
#include <numbers>
#include <random>

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>

#include "shellflow/core/error.h"

namespace shellflow::shell {

ModalResult natural_frequencies(const ShellModel& model, int count, const Eigen::VectorXd& u,
                                const ModalOptions& options) {
  const auto& fixed = model.constrained();
  SparseMatrix K = model.make_matrix();
  SparseMatrix M = model.make_matrix();
  Eigen::VectorXd f;
  model.assemble(u, f, &K);
  model.assemble_mass(M);
  // Supports: identity in K, zero in M (their modes are pushed to infinity).
  for (int col = 0; col < K.outerSize(); ++col) {
    SparseMatrix::InnerIterator itM(M, col);
    for (SparseMatrix::InnerIterator it(K, col); it; ++it, ++itM) {
      if (!fixed[static_cast<std::size_t>(col)] && !fixed[static_cast<std::size_t>(it.row())]) continue;
      it.valueRef() = it.row() == col ? 1.0 : 0.0;
      itM.valueRef() = 0.0;
    }
  }
  Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt(K);
  if (ldlt.info() != Eigen::Success)
    throw SolverError("shell modal analysis: the stiffness matrix is singular; check the supports");

  const Eigen::Index n = K.rows();
  const int p = count + options.extra_vectors;
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> dist(-1.0, 1.0);
  Eigen::MatrixXd X(n, p);
  for (Eigen::Index i = 0; i < X.size(); ++i) X.data()[i] = dist(rng);

  ModalResult result;
  Eigen::VectorXd previous = Eigen::VectorXd::Constant(p, -1.0);
  for (int it = 1; it <= options.max_iterations; ++it) {
    const Eigen::MatrixXd Y = ldlt.solve(Eigen::MatrixXd(M * X));
    const Eigen::MatrixXd Kr = Y.transpose() * (K * Y);
    const Eigen::MatrixXd Mr = Y.transpose() * (M * Y);
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ritz(0.5 * (Kr + Kr.transpose()),
                                                                   0.5 * (Mr + Mr.transpose()));
    if (ritz.info() != Eigen::Success) throw SolverError("shell modal analysis: Rayleigh–Ritz step failed");
    X = Y * ritz.eigenvectors();  // M-orthonormal
    const Eigen::VectorXd lambda = ritz.eigenvalues();
    const double change = ((lambda - previous).head(count).cwiseAbs().array() / lambda.head(count).array()).maxCoeff();
    previous = lambda;
    if (change < options.tolerance) {
      result.iterations = it;
      for (int k = 0; k < count; ++k) {
        result.frequencies.push_back(std::sqrt(lambda(k)) / (2.0 * std::numbers::pi));
        result.modes.emplace_back(X.col(k));
      }
      return result;
    }
  }
  throw SolverError(fmt::format("shell modal analysis: subspace iteration did not converge in {} iterations",
                                options.max_iterations));
}

}  // namespace shellflow::shell
