#include "shellflow/shell/newmark_solver.h"

#include <cmath>

#include "shellflow/core/error.h"

namespace shellflow::shell {

namespace {

double free_norm(const Eigen::VectorXd& v, const std::vector<char>& fixed) {
  double s = 0.0;
  for (Eigen::Index i = 0; i < v.size(); ++i)
    if (!fixed[static_cast<std::size_t>(i)]) s += v(i) * v(i);
  return std::sqrt(s);
}

}  // namespace

NewmarkSolver::NewmarkSolver(const ShellModel& model, NewmarkOptions options,
                             std::function<double(double)> load_factor)
    : model_(model), options_(options), load_factor_(std::move(load_factor)),
      u_(Eigen::VectorXd::Zero(model.num_dofs())), v_(u_), a_(u_), M_(model.make_matrix()),
      K_(model.make_matrix()) {
  model_.assemble_mass(M_);
  inertial_fixed_ = model_.constrained();
  for (Index n = 0; n < model_.num_nodes(); ++n) inertial_fixed_[static_cast<std::size_t>(dofs_per_node * n + 6)] = 1;
}

void NewmarkSolver::set_initial_state(const Eigen::VectorXd& u, const Eigen::VectorXd& v) {
  u_ = u;
  v_ = v;
  for (Index n = 0; n < model_.num_nodes(); ++n) v_(dofs_per_node * n + 6) = 0.0;
  Eigen::VectorXd f_ext = load_factor_at(time_) * model_.reference_load();
  model_.add_follower_loads(u_, load_factor_at(time_), f_ext, nullptr);
  model_.assemble(u_, f_int_, nullptr);
  Eigen::VectorXd rhs = f_ext - f_int_ - options_.mass_damping * (M_ * v_);
  SparseMatrix M = M_;
  NewtonLinearSolver mass_solver;
  if (!mass_solver.solve(M, inertial_fixed_, rhs))
    throw SolverError("shell dynamics: the mass matrix is singular on the position/director dofs");
  a_ = rhs;
}

int NewmarkSolver::try_step(double dt) {
  const double beta = options_.beta, gamma = options_.gamma, cm = options_.mass_damping;
  const double t_next = time_ + dt;
  // Q_s and R_s of shell.md §7 in increments (the y0 terms cancel).
  const Eigen::VectorXd Q = u_ / (beta * dt * dt) + v_ / (beta * dt) + (0.5 / beta - 1.0) * a_;
  const Eigen::VectorXd R = v_ + (1.0 - gamma) * dt * a_;
  const double mass_coefficient = 1.0 / (beta * dt * dt) + cm * gamma / (beta * dt);
  const Eigen::VectorXd MQ = M_ * Q;
  const Eigen::VectorXd inertia_history = -MQ + cm * (M_ * R) - cm * gamma * dt * MQ;
  const auto& fixed = model_.constrained();
  const double lf = load_factor_at(t_next);

  Eigen::VectorXd u = u_;  // predictor y_{s+1}^(0) = y_s (papers' practice)
  for (int it = 1; it <= options_.newton.max_iterations; ++it) {
    if (!model_.assemble(u, f_int_, &K_)) return -1;
    Eigen::VectorXd f_ext = lf * model_.reference_load();
    model_.add_follower_loads(u, lf, f_ext, &K_);
    const Eigen::VectorXd Mu = M_ * u;
    const Eigen::VectorXd g = f_int_ - f_ext + mass_coefficient * Mu + inertia_history;
    // H = K - K_load + (1/(beta dt²) + gamma c_m/(beta dt)) M, on the common pattern.
    double* h = K_.valuePtr();
    const double* m = M_.valuePtr();
    for (Eigen::Index i = 0; i < K_.nonZeros(); ++i) h[i] += mass_coefficient * m[i];
    const double force_scale = std::max({free_norm(f_ext, fixed), free_norm(f_int_, fixed),
                                         free_norm(Mu / (beta * dt * dt) - MQ, fixed)});
    Eigen::VectorXd du = -g;
    if (!linear_solver_.solve(K_, fixed, du, model_.symmetric_tangent())) return -1;
    u += du;
    if (!u.allFinite()) return -1;
    if (newton_converged(model_, options_.newton, du, g, force_scale)) {
      const Eigen::VectorXd a_next = u / (beta * dt * dt) - Q;
      v_ = R + gamma * dt * a_next;
      a_ = a_next;
      for (Index n = 0; n < model_.num_nodes(); ++n) v_(dofs_per_node * n + 6) = a_(dofs_per_node * n + 6) = 0.0;
      u_ = u;
      time_ = t_next;
      return it;
    }
  }
  return -1;
}

int NewmarkSolver::advance(double dt) {
  // Sub-steps of dt / 2^level; one failure halves the remaining sub-steps' size.
  const double t_end = time_ + dt;
  int level = 0, iterations = 0;
  while (time_ < t_end - 1e-12 * dt) {
    const double h = std::min(dt / static_cast<double>(1 << level), t_end - time_);
    const int its = try_step(h);
    if (its < 0) {
      if (++level > options_.newton.max_cutbacks)
        throw SolverError(fmt::format(
            "shell dynamics: Newton did not converge at t = {:.6g} s (step {:.3g} s halved {} times); reduce the "
            "time step or check loads and supports",
            time_ + h, dt, options_.newton.max_cutbacks));
      continue;
    }
    iterations += its;
  }
  time_ = t_end;
  return iterations;
}

}  // namespace shellflow::shell
