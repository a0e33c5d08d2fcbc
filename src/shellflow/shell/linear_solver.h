#pragma once
// The linear solve inside every Newton iteration of the shell solvers.
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <vector>

#include "shellflow/shell/shell_model.h"

namespace shellflow::shell {

/// Sparse solve of the Newton system with the supports eliminated, on the reduced system
/// (free dofs only), ordered once by AMD on the graph of the nodes (7x7 blocks) and copied
/// into a pre-permuted matrix through a precomputed value map: the factorisation then does
/// no fill or work for fixed dofs and Eigen does not permute the matrix again at every
/// factorisation. Symmetric systems: LDLT on the upper triangle. Non-symmetric systems
/// (follower pressure, the linear load hook of NewmarkSolver): SparseLU on the whole reduced
/// matrix with the same ordering (natural ordering inside SparseLU), its pattern analysed
/// once and factorised per call.
class NewtonLinearSolver {
 public:
  /// Zeroes constrained rows/columns of K (diagonal kept, a non-positive one set to 1) and
  /// the constrained entries of rhs, factorises and solves K du = rhs in place of rhs
  /// (constrained entries of du are 0). Returns false when the factorisation fails. The
  /// ordering is analysed again only when the pattern of K or the constraints change.
  bool solve(SparseMatrix& K, const std::vector<char>& constrained, Eigen::VectorXd& rhs, bool symmetric = true);

  /// The two halves of solve(K, ...): eliminate the supports from K and factorise it, then
  /// solve with that factorisation for any number of right-hand sides (e.g. the two of a
  /// bordered / arc-length system, or several modified-Newton iterations). solve(rhs)
  /// zeroes the constrained entries of rhs itself; it returns false when no factorisation
  /// succeeded before.
  bool factorize(SparseMatrix& K, const std::vector<char>& constrained, bool symmetric = true);
  bool solve(Eigen::VectorXd& rhs);

 private:
  void analyse_reduced(const SparseMatrix& K, const std::vector<char>& constrained, bool symmetric);

  using ReducedMatrix = SparseMatrix;
  Eigen::SimplicialLDLT<ReducedMatrix, Eigen::Upper, Eigen::NaturalOrdering<int>> ldlt_;
  Eigen::SparseLU<ReducedMatrix, Eigen::NaturalOrdering<int>> lu_;
  // Reduced, permuted system: reduced_(i, j) (upper triangle when symmetric, else all) =
  // K.valuePtr()[source_[k]].
  ReducedMatrix reduced_;
  std::vector<int> source_;
  std::vector<int> reduced_dof_;  ///< full dof -> position in the reduced system, -1 when fixed
  std::vector<char> analysed_constraints_;
  Eigen::Index analysed_nonzeros_ = -1;
  Eigen::Index analysed_size_ = -1;
  bool analysed_symmetric_ = true;
  Eigen::VectorXd reduced_rhs_;
  std::vector<char> constrained_;  ///< of the last factorisation
  bool symmetric_ = true;
  bool factorized_ = false;
};

/// The Newton system of a ShellModel, in global components: K and every right-hand side are
/// brought to the local frames of the supports along non-axis directions
/// (ShellModel::to_local), the fixed dofs are eliminated, and the correction comes back in
/// global components. Without local frames this is NewtonLinearSolver on the model's
/// constraints. `constrained` replaces the model's flags (in local components), e.g. to
/// also fix the rows without mass in an acceleration solve.
class ShellSystemSolver {
 public:
  explicit ShellSystemSolver(const ShellModel& model, std::vector<char> constrained = {})
      : model_(model), constrained_(std::move(constrained)) {}

  /// Factorises K (changed in place: local components, supports eliminated).
  bool factorize(SparseMatrix& K, bool symmetric);
  bool factorize(SparseMatrix& K) { return factorize(K, model_.symmetric_tangent()); }
  /// Solves with the last factorisation; rhs in, correction out (global components).
  bool solve(Eigen::VectorXd& rhs);
  bool solve(SparseMatrix& K, Eigen::VectorXd& rhs) { return factorize(K) && solve(rhs); }

 private:
  const ShellModel& model_;
  std::vector<char> constrained_;
  NewtonLinearSolver solver_;
};

}  // namespace shellflow::shell
