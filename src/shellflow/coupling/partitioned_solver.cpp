#include "shellflow/coupling/partitioned_solver.h"

#include <fmt/format.h>

#include <chrono>

#include "shellflow/core/error.h"

namespace shellflow::coupling {

PartitionedSolver::PartitionedSolver(shell::ShellModel& model, shell::NewmarkSolver& shell, AerodynamicModel& flow,
                                     ShellStepMotion& motion, PartitionedOptions options)
    : model_(model), shell_(shell), flow_(flow), motion_(motion), options_(options), basis_(model) {
  const std::size_t n = model.load_points().size();
  current_.assign(n, 0.0);
  next_.assign(n, 0.0);
  previous_.assign(n, 0.0);  // the three rotate every step: all of size n
  applied_.assign(n, 0.0);
  point_pressure_.assign(n, 0.0);
  if (flow.sign().size() != n)
    throw Error(fmt::format("coupling: the aerodynamic model has {} load points, the shell {}", flow.sign().size(), n));
  motion_.set_state(shell.time(), shell.displacement(), shell.velocity());
  flow_.pressure_rise(shell.displacement(), shell.velocity(), current_);
  if (!options_.monolithic) {
    // The initial acceleration must balance the loads of t0 too: set them, then let the
    // shell recompute it (its state is otherwise kept).
    apply_loads();
    const Eigen::VectorXd u = shell.displacement(), v = shell.velocity();
    shell.set_initial_state(u, v);
  }
}

void PartitionedSolver::apply_loads() {
  const auto sign = flow_.sign();
  const bool predict = options_.predictor == LoadPredictor::linear && has_previous_;
  for (std::size_t k = 0; k < current_.size(); ++k) {
    applied_[k] = predict ? 2.0 * current_[k] - previous_[k] : current_[k];
    // The gas pushes the wetted face back: along the shell normal N_k (like V) that is
    // -sign_k dp_k (sign_k N_k points into the flow).
    point_pressure_[k] = -sign[k] * applied_[k];
  }
  model_.set_point_pressure(point_pressure_);
}

Vec3 PartitionedSolver::shell_side_force(std::span<const double> dp) const {
  const auto sign = flow_.sign();
  const auto& points = model_.load_points();
  Vec3 f = Vec3::Zero(), x1, x2;
  for (std::size_t k = 0; k < points.size(); ++k) {
    basis_.tangents(model_, k, &shell_.displacement(), x1, x2);
    f += (-sign[k] * dp[k] * basis_.plane_weight[k]) * x1.cross(x2);
  }
  return f;
}

void PartitionedSolver::save(ArchiveWriter& out) const {
  shell_.save(out);
  flow_.save(out);
  out.put(current_);
  out.put(previous_);
  out.put(has_previous_);
}

void PartitionedSolver::restore(ArchiveReader& in) {
  shell_.restore(in);
  flow_.restore(in);
  for (std::vector<double>* loads : {&current_, &previous_}) {
    std::vector<double> stored = in.get_vector<double>();
    in.expect_size("the coupling loads", stored.size(), loads->size());
    *loads = std::move(stored);
  }
  has_previous_ = in.get<bool>();
  motion_.set_state(shell_.time(), shell_.displacement(), shell_.velocity());
}

CouplingStepReport PartitionedSolver::step(double dt) {
  CouplingStepReport report;
  const shell::NewmarkState start = shell_.state();
  using Clock = std::chrono::steady_clock;
  const auto seconds = [](Clock::time_point a) { return std::chrono::duration<double>(Clock::now() - a).count(); };
  for (int k = 1;; ++k) {
    auto c = Clock::now();
    if (!options_.monolithic) apply_loads();
    report.newton_iterations += shell_.advance(dt);
    motion_.set_window(start.time, shell_.time() - start.time, start.u, start.v, shell_.displacement(),
                       shell_.velocity());
    report.shell_seconds += seconds(c);
    try {
      report.flow = flow_.advance(motion_, shell_.time());
    } catch (const SolverError&) {
      // The flow is back at the start of the step: so is the shell.
      shell_.restore(start);
      throw;
    }
    c = Clock::now();
    flow_.pressure_rise(shell_.displacement(), shell_.velocity(), next_);
    report.transfer_seconds += seconds(c);
    report.coupling_iterations = k;
    if (k >= options_.max_iterations) break;
    // An implicit variant would test convergence of `next` against the loads applied, relax
    // (acceleration), restore both solvers to `start` and iterate.
    throw Error("coupling: implicit iterations (max_iterations > 1) are not implemented yet");
  }
  previous_.swap(current_);
  current_.swap(next_);
  has_previous_ = true;
  report.time = shell_.time();
  const auto c = Clock::now();
  report.shell_force = shell_side_force(current_);
  report.fluid_force = flow_.fluid_side_force();
  report.transfer_seconds += seconds(c);
  return report;
}

}  // namespace shellflow::coupling
