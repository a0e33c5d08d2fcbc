#include "shellflow/coupling/partitioned_solver.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>

#include "shellflow/core/error.h"

namespace shellflow::coupling {

namespace {

/// The load points' reference areas: the weights of the coupling residual's norm, once per
/// load component (the pressure rise, then the three shear components of each point).
std::vector<double> reference_areas(const shell::ShellModel& model, const LoadPointBasis& basis, bool shear) {
  const std::size_t n = basis.size();
  std::vector<double> area(shear ? 4 * n : n);
  Vec3 x1, x2;
  for (std::size_t k = 0; k < n; ++k) {
    basis.tangents(model, k, nullptr, x1, x2);
    area[k] = basis.plane_weight[k] * x1.cross(x2).norm();
    if (shear)
      for (std::size_t c = 0; c < 3; ++c) area[n + 3 * k + c] = area[k];
  }
  return area;
}

}  // namespace

PartitionedSolver::PartitionedSolver(shell::ShellModel& model, shell::NewmarkSolver& shell, AerodynamicModel& flow,
                                     ShellStepMotion& motion, PartitionedOptions options)
    : model_(model),
      shell_(shell),
      flow_(flow),
      motion_(motion),
      options_(options),
      basis_(model),
      iterations_(options.iterations, reference_areas(model, basis_, flow.has_shear()),
                  flow.has_shear()
                      ? std::vector<std::size_t>{model.load_points().size(), 3 * model.load_points().size()}
                      : std::vector<std::size_t>{}) {
  const std::size_t n = model.load_points().size();
  if (options_.monolithic && iterations_.implicit())
    throw Error("coupling: the monolithic scheme has no coupling iterations (coupling.iterations must be 1)");
  if (options_.monolithic && flow.has_shear())
    throw Error("coupling: the monolithic scheme takes no shear (piston theory only)");
  const std::size_t size = flow.has_shear() ? 4 * n : n;
  current_.assign(size, 0.0);
  next_.assign(size, 0.0);
  previous_.assign(size, 0.0);  // the three rotate every step: all of one size
  guess_.assign(size, 0.0);
  point_pressure_.assign(n, 0.0);
  if (flow.has_shear()) {
    point_shear_.assign(n, Vec3::Zero());
    reference_jacobian_.resize(n);
    Vec3 x1, x2;
    for (std::size_t k = 0; k < n; ++k) {
      basis_.tangents(model, k, nullptr, x1, x2);
      reference_jacobian_[k] = x1.cross(x2).norm();
    }
  }
  if (flow.sign().size() != n)
    throw Error(fmt::format("coupling: the aerodynamic model has {} load points, the shell {}", flow.sign().size(), n));
  motion_.set_state(shell.time(), shell.displacement(), shell.velocity());
  collect_loads(current_);
  if (!options_.monolithic) {
    // The initial acceleration must balance the loads of t0 too: set them, then let the
    // shell recompute it (its state is otherwise kept).
    apply_loads(current_);
    const Eigen::VectorXd u = shell.displacement(), v = shell.velocity();
    shell.set_initial_state(u, v);
  }
}

void PartitionedSolver::predict() {
  const bool linear = options_.predictor == LoadPredictor::linear && has_previous_;
  for (std::size_t k = 0; k < current_.size(); ++k) guess_[k] = linear ? 2.0 * current_[k] - previous_[k] : current_[k];
}

void PartitionedSolver::collect_loads(std::span<double> loads) {
  const std::size_t n = point_pressure_.size();
  flow_.pressure_rise(shell_.displacement(), shell_.velocity(), loads.first(n));
  if (point_shear_.empty()) return;
  flow_.shear(point_shear_);
  for (std::size_t k = 0; k < n; ++k)
    for (std::size_t c = 0; c < 3; ++c) loads[n + 3 * k + c] = point_shear_[k][Eigen::Index(c)];
}

void PartitionedSolver::apply_loads(std::span<const double> loads) {
  const auto sign = flow_.sign();
  const std::size_t n = point_pressure_.size();
  // The gas pushes the wetted face back: along the shell normal N_k (like V) that is
  // -sign_k dp_k (sign_k N_k points into the flow).
  for (std::size_t k = 0; k < n; ++k) point_pressure_[k] = -sign[k] * loads[k];
  model_.set_point_pressure(point_pressure_);
  if (point_shear_.empty()) return;
  // The shear, per current area, becomes the shell's dead traction per reference area: times
  // the area ratio of the current configuration (coupling.md).
  for (std::size_t k = 0; k < n; ++k)
    point_shear_[k] = area_ratio(k) * Vec3(loads[n + 3 * k], loads[n + 3 * k + 1], loads[n + 3 * k + 2]);
  model_.set_point_traction(point_shear_);
}

double PartitionedSolver::area_ratio(std::size_t k) const {
  Vec3 x1, x2;
  basis_.tangents(model_, k, &shell_.displacement(), x1, x2);
  return x1.cross(x2).norm() / reference_jacobian_[k];
}

Vec3 PartitionedSolver::shell_side_force(std::span<const double> loads) const {
  const auto sign = flow_.sign();
  const std::size_t n = model_.load_points().size();
  const bool shear = loads.size() == 4 * n;
  Vec3 f = Vec3::Zero(), x1, x2;
  for (std::size_t k = 0; k < n; ++k) {
    basis_.tangents(model_, k, &shell_.displacement(), x1, x2);
    f += (-sign[k] * loads[k] * basis_.plane_weight[k]) * x1.cross(x2);
    if (shear)
      f += (basis_.plane_weight[k] * x1.cross(x2).norm()) *
           Vec3(loads[n + 3 * k], loads[n + 3 * k + 1], loads[n + 3 * k + 2]);
  }
  return f;
}

void PartitionedSolver::save(ArchiveWriter& out) const {
  shell_.save(out);
  flow_.save(out);
  out.put(current_);
  out.put(previous_);
  out.put(has_previous_);
  iterations_.save(out);
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
  iterations_.restore(in);
  motion_.set_state(shell_.time(), shell_.displacement(), shell_.velocity());
}

void PartitionedSolver::fail(const shell::NewmarkState& start, const std::string& why) {
  shell_.restore(start);
  flow_.rewind();
  throw SolverError(why);
}

CouplingStepReport PartitionedSolver::step(double dt) {
  CouplingStepReport report;
  const shell::NewmarkState start = shell_.state();
  using Clock = std::chrono::steady_clock;
  const auto seconds = [](Clock::time_point a) { return std::chrono::duration<double>(Clock::now() - a).count(); };
  const bool implicit = iterations_.implicit();
  auto c = Clock::now();
  flow_.mark();  // a copy of the flow's state (for the iterations, and to fail back to the start)
  predict();
  iterations_.begin(guess_);
  report.iteration_seconds += seconds(c);
  for (;;) {
    c = Clock::now();
    if (!options_.monolithic) apply_loads(iterations_.applied());
    report.newton_iterations += shell_.advance(dt);
    motion_.set_window(start.time, shell_.time() - start.time, start.u, start.v, shell_.displacement(),
                       shell_.velocity());
    report.shell_seconds += seconds(c);
    try {
      const FlowStepReport f = flow_.advance(motion_, shell_.time());
      report.flow.substeps = f.substeps;  // per shell step (the last iteration's)
      report.flow.stable_substeps = f.stable_substeps;
      report.flow.mesh_seconds += f.mesh_seconds;
      report.flow.flow_seconds += f.flow_seconds;
    } catch (const SolverError&) {
      // The flow is back at the start of the step: so is the shell.
      shell_.restore(start);
      throw;
    }
    c = Clock::now();
    collect_loads(next_);
    report.transfer_seconds += seconds(c);
    c = Clock::now();
    const auto outcome = iterations_.result(next_);
    report.coupling_iterations = iterations_.iteration();
    report.coupling_residual = iterations_.residual();
    if (outcome == CouplingIterations::Outcome::done) break;
    const double t1 = shell_.time();
    if (outcome == CouplingIterations::Outcome::diverged)
      fail(start,
           fmt::format("t = {:.6g} s: {}{}", t1,
                       std::isfinite(iterations_.residual())
                           ? fmt::format("the loads from the flow missed the predicted ones by more than {} of "
                                         "their size in {} of the last {} steps and grew over {} times their "
                                         "earlier peak (relative load residual now {:.3g}): the coupled run blew "
                                         "up",
                                         CouplingIterations::kBlowUpMiss, CouplingIterations::kBlowUpMissed,
                                         CouplingIterations::kBlowUpWindow, CouplingIterations::kBlowUpGrowth,
                                         iterations_.residual())
                           : std::string("the loads from the flow are no longer finite: the coupled run blew up"),
                       implicit ? ""
                                : "; the explicit staggered scheme is unstable when the gas is heavy next "
                                  "to the shell (docs/coupling.md, added-mass ratio): use coupling."
                                  "acceleration: iqn_ils with coupling.iterations: 20, or a smaller time.step"));
    if (outcome == CouplingIterations::Outcome::not_converged)
      fail(start, fmt::format("t = {:.6g} s: the coupling iterations did not converge in {} iterations (relative "
                              "load residual {:.3e} > coupling.tolerance {:.3e}); raise coupling.iterations, loosen "
                              "coupling.tolerance, or use coupling.acceleration: iqn_ils",
                              t1, iterations_.iteration(), iterations_.residual(), iterations_.options().tolerance));
    shell_.rewind(start);
    flow_.rewind();
    report.iteration_seconds += seconds(c);
  }
  previous_.swap(current_);
  current_.swap(next_);
  has_previous_ = true;
  report.time = shell_.time();
  c = Clock::now();
  report.shell_force = shell_side_force(current_);
  report.fluid_force = flow_.fluid_side_force();
  report.transfer_seconds += seconds(c);
  return report;
}

}  // namespace shellflow::coupling
