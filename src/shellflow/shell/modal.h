#pragma once
// Small-amplitude natural frequencies of a supported shell about a state u:
// K(u) phi = omega^2 M phi. The thickness parameter `a` carries no mass (shell.md §6); it is
// condensed out implicitly, because the iteration works with K^-1 M (static condensation of
// the massless dofs is exactly what K^-1 does).
#include <vector>

#include "shellflow/shell/shell_model.h"

namespace shellflow::shell {

struct ModalOptions {
  int extra_vectors = 8;  ///< subspace size = count + extra_vectors
  /// On the relative change of every wanted eigenvalue. The round-off floor is ~1e-9: the
  /// transverse-normal stiffness (~E/h) makes K ill-conditioned.
  double tolerance = 1e-8;
  int max_iterations = 300;
};

struct ModalResult {
  std::vector<double> frequencies;     ///< Hz, ascending
  std::vector<Eigen::VectorXd> modes;  ///< M-normalised, full dof vectors
  int iterations = 0;
};

/// Lowest `count` natural frequencies by subspace iteration with Rayleigh–Ritz on the sparse
/// LDLT factor of K. Throws SolverError when K is singular (insufficient supports) or the
/// iteration does not converge.
ModalResult natural_frequencies(const ShellModel& model, int count, const Eigen::VectorXd& u,
                                const ModalOptions& options = {});

}  // namespace shellflow::shell
