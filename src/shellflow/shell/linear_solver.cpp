#include "shellflow/shell/linear_solver.h"

namespace shellflow::shell {

bool NewtonLinearSolver::solve(SparseMatrix& K, const std::vector<char>& constrained, Eigen::VectorXd& rhs,
                               bool symmetric) {
  // Supports: identity rows/columns scaled by the original diagonal (no penalties).
  for (int col = 0; col < K.outerSize(); ++col) {
    const bool col_fixed = constrained[static_cast<std::size_t>(col)] != 0;
    for (SparseMatrix::InnerIterator it(K, col); it; ++it) {
      if (!col_fixed && !constrained[static_cast<std::size_t>(it.row())]) continue;
      if (it.row() == col) {
        if (!(it.value() > 0.0)) it.valueRef() = 1.0;
      } else {
        it.valueRef() = 0.0;
      }
    }
    if (col_fixed) rhs(col) = 0.0;
  }
  if (!symmetric) {
    if (!lu_analysed_) {
      lu_.analyzePattern(K);
      lu_analysed_ = true;
    }
    lu_.factorize(K);
    if (lu_.info() != Eigen::Success) return false;
    rhs = lu_.solve(rhs).eval();
    return lu_.info() == Eigen::Success && rhs.allFinite();
  }
  if (!analysed_) {
    ldlt_.analyzePattern(K);
    analysed_ = true;
  }
  ldlt_.factorize(K);
  if (ldlt_.info() != Eigen::Success) return false;
  rhs = ldlt_.solve(rhs);
  return ldlt_.info() == Eigen::Success && rhs.allFinite();
}

}  // namespace shellflow::shell
