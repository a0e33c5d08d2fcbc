#pragma once
// Dynamics: Newmark (beta = 1/4, gamma = 1/2 by default) in the positional form of shell.md
// §7, written in the increments u = y - y0, with Newton in every step (§8), mass-
// proportional damping C = c_m M, and step halving on failure.
#include <functional>

#include "shellflow/shell/static_solver.h"

namespace shellflow::shell {

struct NewmarkOptions {
  double beta = 0.25;
  double gamma = 0.5;
  double mass_damping = 0.0;  ///< c_m in C = c_m M (1/s)
  NewtonOptions newton;
};

class NewmarkSolver {
 public:
  /// `load_factor(t)` multiplies the model's dead loads (and edge couples); default 0.
  NewmarkSolver(const ShellModel& model, NewmarkOptions options = {},
                std::function<double(double)> load_factor = {});

  /// Sets the initial state (u, v at the current time; u = 0 at rest) and computes the
  /// consistent acceleration from M a = F_ext - F_int - C v on the x and G rows.
  void set_initial_state(const Eigen::VectorXd& u, const Eigen::VectorXd& v);
  /// Advances by dt (sub-stepping by halves on failure, up to newton.max_cutbacks levels).
  /// Returns the Newton iterations used. Throws SolverError naming the time on failure.
  int advance(double dt);

  double time() const { return time_; }
  const Eigen::VectorXd& displacement() const { return u_; }
  const Eigen::VectorXd& velocity() const { return v_; }
  const Eigen::VectorXd& acceleration() const { return a_; }
  double kinetic_energy() const { return 0.5 * v_.dot(M_ * v_); }
  double strain_energy() const { return model_.strain_energy(u_); }
  const SparseMatrix& mass() const { return M_; }

 private:
  /// One Newmark step of size dt; -1 (state unchanged) when Newton fails.
  int try_step(double dt);
  double load_factor_at(double t) const { return load_factor_ ? load_factor_(t) : 0.0; }

  const ShellModel& model_;
  NewmarkOptions options_;
  std::function<double(double)> load_factor_;
  double time_ = 0.0;
  Eigen::VectorXd u_, v_, a_;
  SparseMatrix M_, K_;
  Eigen::VectorXd f_int_;
  NewtonLinearSolver linear_solver_;
  std::vector<char> inertial_fixed_;  ///< constrained dofs plus every `a` (no inertia)
};

}  // namespace shellflow::shell
