#include "shellflow/shell/static_solver.h"

#include <cmath>
#include <limits>

#include "shellflow/core/error.h"

namespace shellflow::shell {

namespace {

double free_norm(const Eigen::VectorXd& v, const std::vector<char>& constrained) {
  double s = 0.0;
  for (Eigen::Index i = 0; i < v.size(); ++i)
    if (!constrained[static_cast<std::size_t>(i)]) s += v(i) * v(i);
  return std::sqrt(s);
}

}  // namespace

bool newton_converged(const ShellModel& model, const NewtonOptions& options, const Eigen::VectorXd& du,
                      const Eigen::VectorXd& g, double force_scale) {
  double dx2 = 0.0, dG2 = 0.0, da = 0.0;
  for (Index n = 0; n < model.num_nodes(); ++n) {
    dx2 += du.segment<3>(dofs_per_node * n).squaredNorm();
    dG2 += du.segment<3>(dofs_per_node * n + 3).squaredNorm();
    da = std::max(da, std::abs(du(dofs_per_node * n + 6)));
  }
  const double sqrt_n = std::sqrt(static_cast<double>(model.num_nodes()));
  const double g_norm = free_norm(g, model.constrained());
  return std::sqrt(dx2) <= options.tolerance * model.reference_length() * sqrt_n &&
         std::sqrt(dG2) <= options.tolerance * sqrt_n && da <= options.tolerance &&
         g_norm <= options.residual_tolerance * std::max(force_scale, std::numeric_limits<double>::min());
}

StaticSolver::StaticSolver(const ShellModel& model, NewtonOptions options)
    : model_(model), options_(options), u_(Eigen::VectorXd::Zero(model.num_dofs())), K_(model.make_matrix()) {}

int StaticSolver::solve(double load_factor) {
  const Eigen::VectorXd u_start = u_;
  const auto& fixed = model_.constrained();
  Eigen::VectorXd f_ext;
  for (int it = 1; it <= options_.max_iterations; ++it) {
    if (!model_.assemble(u_, f_int_, &K_)) break;
    f_ext = load_factor * model_.reference_load();
    model_.add_follower_loads(u_, load_factor, f_ext, &K_);
    Eigen::VectorXd rhs = f_ext - f_int_;  // -g
    const double force_scale = std::max(free_norm(f_ext, fixed), free_norm(f_int_, fixed));
    const Eigen::VectorXd residual = -rhs;
    if (!linear_solver_.solve(K_, fixed, rhs, model_.symmetric_tangent())) break;
    u_ += rhs;
    if (!u_.allFinite()) break;
    // The residual tested is the one before this correction; together with a small
    // correction it certifies the state reached.
    if (newton_converged(model_, options_, rhs, residual, force_scale)) {
      load_factor_ = load_factor;
      return it;
    }
  }
  u_ = u_start;
  return -1;
}

std::vector<LoadStep> StaticSolver::run(int num_steps, double final_load_factor,
                                        const std::function<void(const LoadStep&)>& on_step) {
  std::vector<LoadStep> steps;
  const double start = load_factor_;
  for (int s = 1; s <= num_steps; ++s) {
    const double target = start + (final_load_factor - start) * s / num_steps;
    // Sub-increments towards `target`, halved on failure.
    double increment = target - load_factor_;
    int cutbacks = 0;
    int iterations = 0;
    while (load_factor_ != target) {
      const double next = std::abs(target - load_factor_) <= std::abs(increment) ? target : load_factor_ + increment;
      const int its = solve(next);
      if (its < 0) {
        if (++cutbacks > options_.max_cutbacks)
          throw SolverError(fmt::format(
              "shell statics: Newton did not converge at load factor {:.6g} (step {} of {}) after {} cut-backs; "
              "use more load steps or check supports and loads",
              next, s, num_steps, options_.max_cutbacks));
        increment *= 0.5;
        continue;
      }
      iterations += its;
      cutbacks = 0;
    }
    steps.push_back({load_factor_, iterations});
    if (on_step) on_step(steps.back());
  }
  return steps;
}

}  // namespace shellflow::shell
