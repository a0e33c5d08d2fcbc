#pragma once
// Static analysis: load stepping with Newton–Raphson on the dead loads of a ShellModel
// (shell.md §7 "Statics", §8), with step cut-back on failure.
#include <functional>
#include <vector>

#include "shellflow/shell/linear_solver.h"
#include "shellflow/shell/shell_model.h"

namespace shellflow::shell {

/// Convergence criteria of shell.md §8 (defaults as there).
struct NewtonOptions {
  double tolerance = 1e-8;           ///< on increments of x (× L_ref √N), G (× √N), a (max)
  double residual_tolerance = 1e-6;  ///< on ‖g‖ relative to the force scale
  int max_iterations = 25;
  int max_cutbacks = 5;              ///< halvings of a failed increment before giving up
};

/// Result of one converged load level.
struct LoadStep {
  double load_factor = 0.0;
  int iterations = 0;
};

class StaticSolver {
 public:
  explicit StaticSolver(const ShellModel& model, NewtonOptions options = {});

  /// Newton from the current state to equilibrium at `load_factor`. Returns the number of
  /// iterations, or -1 (state restored) when it does not converge.
  int solve(double load_factor);
  /// Loads from the current factor to `final_load_factor` in `num_steps` equal increments,
  /// halving an increment that fails (up to max_cutbacks times in a row); calls
  /// `on_step` after every converged level. Throws SolverError naming the level when the
  /// cut-backs are exhausted.
  std::vector<LoadStep> run(int num_steps, double final_load_factor,
                            const std::function<void(const LoadStep&)>& on_step = {});

  const Eigen::VectorXd& displacement() const { return u_; }
  double load_factor() const { return load_factor_; }
  const ShellModel& model() const { return model_; }

 private:
  const ShellModel& model_;
  NewtonOptions options_;
  Eigen::VectorXd u_;
  double load_factor_ = 0.0;
  SparseMatrix K_;
  Eigen::VectorXd f_int_;
  NewtonLinearSolver linear_solver_;
};

/// The convergence test of shell.md §8 on one Newton correction `du` and residual `g` (free
/// dofs only). `force_scale` is max(‖F_ext‖, ‖F_int‖, ‖M ÿ‖) on free dofs. Positions are
/// scaled by the bounding-box diagonal, not by the norm of the initial positions as in O2P2,
/// which would depend on where the origin is (the spec's correction).
bool newton_converged(const ShellModel& model, const NewtonOptions& options, const Eigen::VectorXd& du,
                      const Eigen::VectorXd& g, double force_scale);

}  // namespace shellflow::shell
