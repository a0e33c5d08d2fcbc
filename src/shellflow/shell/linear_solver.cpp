#include "shellflow/shell/linear_solver.h"

#include <Eigen/OrderingMethods>

namespace shellflow::shell {

namespace {

/// Supports: identity rows/columns scaled by the original diagonal (no penalties), so that
/// K keeps its pattern and symmetry for callers that use it after the solve.
void eliminate_supports(SparseMatrix& K, const std::vector<char>& constrained) {
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
  }
}

}  // namespace

// Ordering on the node graph: the dofs of a node share their column pattern, so AMD on the
// nodes (7x fewer vertices) orders as well as AMD on the dofs and keeps each node's free
// dofs consecutive (denser columns of L).
void NewtonLinearSolver::analyse_reduced(const SparseMatrix& K, const std::vector<char>& constrained, bool symmetric) {
  const Eigen::Index n = K.rows();
  const int block = n % dofs_per_node == 0 ? dofs_per_node : 1;
  const Eigen::Index num_blocks = n / block;
  std::vector<Eigen::Triplet<double, int>> node_entries;
  node_entries.reserve(static_cast<std::size_t>(K.nonZeros() / (block * block) + num_blocks));
  for (int col = 0; col < K.outerSize(); col += block)
    for (SparseMatrix::InnerIterator it(K, col); it; ++it)
      if (it.row() % block == 0) node_entries.emplace_back(it.row() / block, col / block, 1.0);
  SparseMatrix node_graph(num_blocks, num_blocks);
  node_graph.setFromTriplets(node_entries.begin(), node_entries.end());
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> order;  // position -> node
  Eigen::AMDOrdering<int>()(node_graph, order);

  reduced_dof_.assign(static_cast<std::size_t>(n), -1);
  int next = 0;
  for (Eigen::Index k = 0; k < num_blocks; ++k)
    for (int d = 0; d < block; ++d) {
      const auto dof = static_cast<std::size_t>(order.indices()(k) * block + d);
      if (!constrained[dof]) reduced_dof_[dof] = next++;
    }
  // Upper triangle (or all) of the permuted reduced matrix; the values of the triplets carry
  // the index of the source entry in K (exact in a double) and become the value map.
  std::vector<Eigen::Triplet<double, int>> entries;
  entries.reserve(static_cast<std::size_t>(symmetric ? K.nonZeros() / 2 + n : K.nonZeros()));
  for (int col = 0; col < K.outerSize(); ++col) {
    const int pc = reduced_dof_[static_cast<std::size_t>(col)];
    if (pc < 0) continue;
    for (SparseMatrix::InnerIterator it(K, col); it; ++it) {
      const int pr = reduced_dof_[static_cast<std::size_t>(it.row())];
      if (pr >= 0 && (pr <= pc || !symmetric))
        entries.emplace_back(pr, pc, static_cast<double>(&it.value() - K.valuePtr()));
    }
  }
  reduced_.resize(next, next);
  reduced_.setFromTriplets(entries.begin(), entries.end());
  reduced_.makeCompressed();
  source_.resize(static_cast<std::size_t>(reduced_.nonZeros()));
  for (Eigen::Index k = 0; k < reduced_.nonZeros(); ++k)
    source_[static_cast<std::size_t>(k)] = static_cast<int>(reduced_.valuePtr()[k]);
  if (next > 0) {
    if (symmetric)
      ldlt_.analyzePattern(reduced_);
    else
      lu_.analyzePattern(reduced_);
  }
  reduced_rhs_.resize(next);
  analysed_symmetric_ = symmetric;
  analysed_constraints_ = constrained;
  analysed_nonzeros_ = K.nonZeros();
  analysed_size_ = n;
}

bool NewtonLinearSolver::factorize(SparseMatrix& K, const std::vector<char>& constrained, bool symmetric) {
  factorized_ = false;
  eliminate_supports(K, constrained);
  constrained_ = constrained;
  symmetric_ = symmetric;
  if (analysed_size_ != K.rows() || analysed_nonzeros_ != K.nonZeros() || analysed_constraints_ != constrained ||
      analysed_symmetric_ != symmetric)
    analyse_reduced(K, constrained, symmetric);
  if (reduced_.rows() == 0) {
    factorized_ = true;
    return true;
  }
  const double* values = K.valuePtr();
  double* reduced_values = reduced_.valuePtr();
  for (std::size_t k = 0; k < source_.size(); ++k) reduced_values[k] = values[source_[k]];
  if (symmetric) {
    ldlt_.factorize(reduced_);
    factorized_ = ldlt_.info() == Eigen::Success;
  } else {
    lu_.factorize(reduced_);
    factorized_ = lu_.info() == Eigen::Success;
  }
  return factorized_;
}

bool NewtonLinearSolver::solve(Eigen::VectorXd& rhs) {
  if (!factorized_) return false;
  for (std::size_t i = 0; i < constrained_.size(); ++i)
    if (constrained_[i]) rhs(static_cast<Eigen::Index>(i)) = 0.0;
  if (reduced_.rows() == 0) {
    rhs.setZero();
    return true;
  }
  for (std::size_t i = 0; i < reduced_dof_.size(); ++i)
    if (reduced_dof_[i] >= 0) reduced_rhs_(reduced_dof_[i]) = rhs(static_cast<Eigen::Index>(i));
  if (symmetric_) {
    reduced_rhs_ = ldlt_.solve(reduced_rhs_).eval();
    if (ldlt_.info() != Eigen::Success) return false;
  } else {
    reduced_rhs_ = lu_.solve(reduced_rhs_).eval();
    if (lu_.info() != Eigen::Success) return false;
  }
  for (std::size_t i = 0; i < reduced_dof_.size(); ++i)
    rhs(static_cast<Eigen::Index>(i)) = reduced_dof_[i] >= 0 ? reduced_rhs_(reduced_dof_[i]) : 0.0;
  return rhs.allFinite();
}

bool NewtonLinearSolver::solve(SparseMatrix& K, const std::vector<char>& constrained, Eigen::VectorXd& rhs,
                               bool symmetric) {
  return factorize(K, constrained, symmetric) && solve(rhs);
}

bool ShellSystemSolver::factorize(SparseMatrix& K, bool symmetric) {
  model_.to_local(K);
  return solver_.factorize(K, constrained_.empty() ? model_.constrained() : constrained_, symmetric);
}

bool ShellSystemSolver::solve(Eigen::VectorXd& rhs) {
  model_.to_local(rhs);
  if (!solver_.solve(rhs)) return false;
  model_.to_global(rhs);
  return true;
}

}  // namespace shellflow::shell
