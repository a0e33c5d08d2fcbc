#pragma once
// The linear solve inside every Newton iteration of the shell solvers.
#include <vector>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>

#include "shellflow/shell/shell_model.h"

namespace shellflow::shell {

/// Sparse solve of the Newton system with supports eliminated by replacing their rows and
/// columns with the identity (keeps the pattern and the symmetry). LDLT for symmetric
/// systems (measured 2-3x faster than SparseLU on the strip), SparseLU for non-symmetric ones
/// (follower pressure). The ordering is analysed once.
class NewtonLinearSolver {
 public:
  /// Zeroes constrained rows/columns of K (diagonal kept) and of rhs, factorises and solves
  /// K du = rhs in place of rhs. Returns false when the factorisation fails.
  bool solve(SparseMatrix& K, const std::vector<char>& constrained, Eigen::VectorXd& rhs, bool symmetric = true);

 private:
  Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt_;
  Eigen::SparseLU<SparseMatrix, Eigen::COLAMDOrdering<int>> lu_;
  bool analysed_ = false;
  bool lu_analysed_ = false;
};

}  // namespace shellflow::shell
