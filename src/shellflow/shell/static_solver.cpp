#include "shellflow/shell/static_solver.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <string_view>

#include "shellflow/core/error.h"

namespace shellflow::shell {

namespace {

/// Force scale of the §8 residual test: max(‖F_ext‖, ‖F_int‖) on the free dofs, and also
/// the reactions (F_int on the fixed dofs) — without them a problem driven only by
/// prescribed support displacements has a zero scale at equilibrium and never converges.
double force_scale_of(const ShellModel& model, const Eigen::VectorXd& f_ext, const Eigen::VectorXd& f_int) {
  return std::max({model.free_norm(f_ext), model.free_norm(f_int), model.fixed_norm(f_int)});
}

/// Moves a path parameter (load factor or controlled displacement) from `current` to
/// `target`: the whole remainder first, an increment halved after each failure and kept
/// after a success. `solve_at(value)` returns its Newton iterations, or -1 (state restored).
/// Returns the iterations used, or -1 after `max_cutbacks` failures in a row, with the value
/// that failed last in `failed_at`.
template <class SolveAt>
int step_with_cutbacks(double current, double target, int max_cutbacks, SolveAt&& solve_at, double& failed_at) {
  double increment = target - current;
  int cutbacks = 0, iterations = 0;
  while (current != target) {
    const double next = std::abs(target - current) <= std::abs(increment) ? target : current + increment;
    const int its = solve_at(next);
    if (its < 0) {
      if (++cutbacks > max_cutbacks) {
        failed_at = next;
        return -1;
      }
      increment *= 0.5;
      continue;
    }
    iterations += its;
    cutbacks = 0;
    current = next;
  }
  return iterations;
}

/// Prescribed support motions follow the load factor, so they only go with load control.
void require_no_prescribed_motion(const ShellModel& model, std::string_view method) {
  if (model.has_prescribed_motion())
    throw InputError(
        fmt::format("shell mesh '{}': prescribed support motion needs load control; {} varies the "
                    "load factor inside a step; use control: load",
                    model.mesh().name, method));
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
  const double g_norm = model.free_norm(g);
  // Floor of the force scale: a residual below 1e-12 E h L_ref is a strain of 1e-12, i.e.
  // round-off. Without it a motion with no forces at all (a prescribed rigid motion) has a
  // zero scale and never converges.
  const ShellSection& section = model.section();
  force_scale = std::max(force_scale, 1e-6 * section.material.young * section.thickness * model.reference_length());
  return std::sqrt(dx2) <= options.tolerance * model.reference_length() * sqrt_n &&
         std::sqrt(dG2) <= options.tolerance * sqrt_n && da <= options.tolerance &&
         g_norm <= options.residual_tolerance * std::max(force_scale, std::numeric_limits<double>::min());
}

StaticSolver::StaticSolver(const ShellModel& model, NewtonOptions options)
    : model_(model),
      options_(options),
      u_(Eigen::VectorXd::Zero(model.num_dofs())),
      K_(model.make_matrix()),
      linear_solver_(model) {
  model_.apply_prescribed(0.0, u_);
}

int StaticSolver::solve(double load_factor) {
  const Eigen::VectorXd u_start = u_;
  if (!predict_prescribed(load_factor)) {
    u_ = u_start;
    return -1;
  }
  Eigen::VectorXd f_ext;
  double last_residual = 0.0;
  for (int it = 1; it <= options_.max_iterations; ++it) {
    // Modified Newton keeps the factorised tangent (of an earlier iteration or level) until
    // an iteration contracts the residual by less than refresh_ratio.
    const bool new_tangent = !options_.modified || !tangent_kept_;
    if (!model_.assemble(u_, f_int_, new_tangent ? &K_ : nullptr)) break;
    f_ext = load_factor * model_.reference_load();
    model_.add_follower_loads(u_, load_factor, load_factor, f_ext, new_tangent ? &K_ : nullptr);
    Eigen::VectorXd rhs = f_ext - f_int_;  // -g
    const double force_scale = force_scale_of(model_, f_ext, f_int_);
    const Eigen::VectorXd residual = -rhs;
    const double residual_norm = model_.free_norm(rhs);
    if (options_.modified && it > 1 && residual_norm > options_.refresh_ratio * last_residual && !new_tangent) {
      tangent_kept_ = false;  // poor contraction: this iteration again with a new tangent
      --it;
      continue;
    }
    last_residual = residual_norm;
    if (new_tangent) {
      tangent_kept_ = linear_solver_.factorize(K_);
      if (!tangent_kept_) break;
    }
    if (!linear_solver_.solve(rhs)) break;
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
  tangent_kept_ = false;
  return -1;
}

// Supports with prescribed motion move to their values at this level (the load factor is
// the pseudo-time of a static run). A jump of those dofs alone would distort the first row
// of elements and give Newton a poor start, so one linear step with the tangent of the
// current state carries it into the free dofs: u = target + K⁻¹(F_ext − F_int − K jump).
bool StaticSolver::predict_prescribed(double load_factor) {
  if (!model_.has_prescribed_motion()) return true;
  Eigen::VectorXd target = u_;
  model_.apply_prescribed(load_factor, target);
  const Eigen::VectorXd jump = target - u_;
  if (!(jump.squaredNorm() > 0.0)) return true;
  if (!model_.assemble(u_, f_int_, &K_)) return false;
  Eigen::VectorXd rhs = load_factor * model_.reference_load();
  model_.add_follower_loads(u_, load_factor, load_factor, rhs, &K_);
  rhs -= f_int_ + K_ * jump;
  tangent_kept_ = false;
  if (!linear_solver_.solve(K_, rhs)) return false;
  u_ = target + rhs;
  return u_.allFinite();
}

std::vector<LoadStep> StaticSolver::run(int num_steps, double final_load_factor,
                                        const std::function<void(const LoadStep&)>& on_step) {
  std::vector<LoadStep> steps;
  const double start = load_factor_;
  for (int s = 1; s <= num_steps; ++s) {
    const double target = start + (final_load_factor - start) * s / num_steps;
    double failed_at = 0.0;
    const int iterations = step_with_cutbacks(
        load_factor_, target, options_.max_cutbacks, [&](double next) { return solve(next); }, failed_at);
    if (iterations < 0)
      throw SolverError(fmt::format(
          "shell statics: Newton did not converge at load factor {:.6g} (step {} of {}) after {} cut-backs; "
          "use more load steps or check supports and loads",
          failed_at, s, num_steps, options_.max_cutbacks));
    steps.push_back({load_factor_, iterations, 0.0});
    if (on_step) on_step(steps.back());
  }
  return steps;
}

void StaticSolver::set_state(const Eigen::VectorXd& u, double load_factor) {
  if (u.size() != model_.num_dofs())
    throw InputError(
        fmt::format("shell statics: state has {} entries, the model has {} dofs", u.size(), model_.num_dofs()));
  u_ = u;
  load_factor_ = load_factor;
  last_increment_.resize(0);
  tangent_kept_ = false;
}

Eigen::VectorXd StaticSolver::load_direction() const {
  Eigen::VectorXd q = model_.reference_load();
  model_.add_follower_load_direction(u_, load_factor_, q);
  return q;
}

double StaticSolver::relative_residual() const {
  Eigen::VectorXd f_int;
  if (!model_.assemble(u_, f_int, nullptr)) return std::numeric_limits<double>::infinity();
  Eigen::VectorXd f_ext = load_factor_ * model_.reference_load();
  model_.add_follower_loads(u_, load_factor_, load_factor_, f_ext, nullptr);
  const double scale = force_scale_of(model_, f_ext, f_int);
  return model_.free_norm(f_int - f_ext) / std::max(scale, std::numeric_limits<double>::min());
}

bool StaticSolver::assemble_system(double load_factor, Eigen::VectorXd& residual, Eigen::VectorXd& direction,
                                   double& force_scale) {
  if (!model_.assemble(u_, f_int_, &K_)) return false;
  Eigen::VectorXd f_ext = load_factor * model_.reference_load();
  model_.add_follower_loads(u_, load_factor, load_factor, f_ext, &K_);
  direction = load_direction();
  residual = f_int_ - f_ext;
  force_scale = force_scale_of(model_, f_ext, f_int_);
  return residual.allFinite();
}

bool StaticSolver::solve_pair(Eigen::VectorXd& minus_g_then_du_r, Eigen::VectorXd& q_then_du_t) {
  tangent_kept_ = false;
  return linear_solver_.factorize(K_) && linear_solver_.solve(minus_g_then_du_r) && linear_solver_.solve(q_then_du_t);
}

double StaticSolver::position_dot(const Eigen::VectorXd& a, const Eigen::VectorXd& b) const {
  Eigen::VectorXd a_free = a, b_free = b;
  model_.remove_fixed_part(a_free);
  model_.remove_fixed_part(b_free);
  double s = 0.0;
  for (Index n = 0; n < model_.num_nodes(); ++n)
    s += a_free.segment<3>(dofs_per_node * n).dot(b_free.segment<3>(dofs_per_node * n));
  return s;
}

Eigen::VectorXd StaticSolver::control_weights(const ControlledDisplacement& control) const {
  if (control.component < 0 || control.component > 2)
    throw InputError(fmt::format("displacement control: component {} is not a global axis; use 0 (x), 1 (y) or 2 (z)",
                                 control.component));
  Eigen::VectorXd w = Eigen::VectorXd::Zero(model_.num_dofs());
  if (control.node >= 0) {
    if (control.node >= model_.num_nodes())
      throw InputError(fmt::format("displacement control: node {} does not exist (the mesh has {} nodes)", control.node,
                                   model_.num_nodes()));
    w(dofs_per_node * control.node + control.component) = 1.0;
  } else {
    const auto& nodes = model_.mesh().group(control.group).nodes;
    if (nodes.empty()) throw InputError(fmt::format("displacement control: group '{}' has no nodes", control.group));
    for (Index n : nodes) w(dofs_per_node * n + control.component) = 1.0 / static_cast<double>(nodes.size());
  }
  if (!(model_.free_norm(w) > 1e-12 * w.norm()))
    throw InputError(fmt::format(
        "displacement control: component {} of {} is fixed by a support; control a free "
        "displacement",
        control.component,
        control.node >= 0 ? fmt::format("node {}", control.node) : fmt::format("group '{}'", control.group)));
  return w;
}

double StaticSolver::controlled_displacement(const ControlledDisplacement& control) const {
  return control_weights(control).dot(u_);
}

int StaticSolver::solve_displacement(const ControlledDisplacement& control, double value) {
  require_no_prescribed_motion(model_, "displacement control");
  const Eigen::VectorXd w = control_weights(control);
  const Eigen::VectorXd u_start = u_;
  const double load_start = load_factor_;
  Eigen::VectorXd g, q;
  double force_scale = 0.0;
  for (int it = 1; it <= options_.max_iterations; ++it) {
    if (!assemble_system(load_factor_, g, q, force_scale)) break;
    Eigen::VectorXd du_r = -g;
    if (!solve_pair(du_r, q)) break;
    // Bordered solve of [K -q; wᵀ 0] [δu; δλ] = [-g; value - wᵀu].
    const double w_t = w.dot(q);
    if (!(std::abs(w_t) > 0.0)) break;  // the control does not move with the load
    const double d_load = (value - w.dot(u_ + du_r)) / w_t;
    const Eigen::VectorXd du = du_r + d_load * q;
    if (!du.allFinite()) break;
    const bool converged = newton_converged(model_, options_, du, g, force_scale);
    u_ += du;
    load_factor_ += d_load;
    if (converged) return it;
  }
  u_ = u_start;
  load_factor_ = load_start;
  return -1;
}

std::vector<LoadStep> StaticSolver::run_displacement_control(const ControlledDisplacement& control, int num_steps,
                                                             double final_value,
                                                             const std::function<void(const LoadStep&)>& on_step) {
  require_no_prescribed_motion(model_, "displacement control");
  std::vector<LoadStep> steps;
  double current = controlled_displacement(control);
  const double start = current;
  for (int s = 1; s <= num_steps; ++s) {
    const double target = start + (final_value - start) * s / num_steps;
    double failed_at = 0.0;
    const int iterations = step_with_cutbacks(
        current, target, options_.max_cutbacks, [&](double next) { return solve_displacement(control, next); },
        failed_at);
    if (iterations < 0)
      throw SolverError(fmt::format(
          "shell statics: displacement control did not converge at controlled displacement {:.6g} (step {} of "
          "{}, load factor {:.6g}) after {} cut-backs; use more steps, or the arc-length method past a "
          "displacement limit point",
          failed_at, s, num_steps, load_factor_, options_.max_cutbacks));
    current = target;
    steps.push_back({load_factor_, iterations, 0.0});
    if (on_step) on_step(steps.back());
  }
  return steps;
}

int StaticSolver::arc_length_step(double arc_length, double direction_sign) {
  const Eigen::VectorXd u_start = u_;
  const double load_start = load_factor_;
  const auto fail = [&] {
    u_ = u_start;
    load_factor_ = load_start;
    return -1;
  };
  Eigen::VectorXd g, q;
  double force_scale = 0.0;
  // Predictor along the tangent K δu_t = q, ‖Δx‖ = Δl. Its sign follows the previous step's
  // increment (positive work along the path), so the path does not double back at a limit
  // point where the sign of λ̇ changes.
  if (!assemble_system(load_factor_, g, q, force_scale)) return fail();
  tangent_kept_ = false;
  if (!linear_solver_.solve(K_, q)) return fail();
  const double t_norm = std::sqrt(position_dot(q, q));
  if (!(t_norm > 0.0)) return fail();
  double sign = direction_sign;
  if (last_increment_.size() == u_.size()) {
    const double turn = position_dot(last_increment_, q);
    if (turn != 0.0) sign = turn > 0.0 ? 1.0 : -1.0;
  }
  const double d_load_predictor = sign * arc_length / t_norm;
  Eigen::VectorXd du_step = d_load_predictor * q;
  u_ += du_step;
  load_factor_ += d_load_predictor;
  for (int it = 1; it <= options_.max_iterations; ++it) {
    if (!assemble_system(load_factor_, g, q, force_scale)) return fail();
    Eigen::VectorXd du_r = -g;
    if (!solve_pair(du_r, q)) return fail();
    // ‖Δu + δu_r + δλ δu_t‖² = Δl² over positions: a1 δλ² + a2 δλ + a3 = 0.
    const Eigen::VectorXd base = du_step + du_r;
    const double a1 = position_dot(q, q), a2 = 2.0 * position_dot(q, base),
                 a3 = position_dot(base, base) - arc_length * arc_length;
    const double discriminant = a2 * a2 - 4.0 * a1 * a3;
    if (!(a1 > 0.0) || !(discriminant >= 0.0)) return fail();
    const double root = std::sqrt(discriminant);
    // Stable roots (no cancellation), then the one whose new increment is closest in
    // direction to the current one (Crisfield's choice; the other one turns back).
    const double qroot = -0.5 * (a2 + (a2 >= 0.0 ? root : -root));
    const double r1 = qroot / a1, r2 = qroot != 0.0 ? a3 / qroot : -r1;
    const double base_dot = position_dot(du_step, base), q_dot = position_dot(du_step, q);
    const double d_load = base_dot + r1 * q_dot >= base_dot + r2 * q_dot ? r1 : r2;
    const Eigen::VectorXd du = du_r + d_load * q;
    if (!du.allFinite()) return fail();
    const bool converged = newton_converged(model_, options_, du, g, force_scale);
    u_ += du;
    load_factor_ += d_load;
    du_step += du;
    if (converged) {
      last_increment_ = du_step;
      return it;
    }
  }
  return fail();
}

std::vector<LoadStep> StaticSolver::run_arc_length(int max_steps, const ArcLengthOptions& options,
                                                   const PathCallback& on_step) {
  require_no_prescribed_motion(model_, "the arc-length method");
  if (!(options.initial_load_increment != 0.0) || options.desired_iterations < 1 || !(options.max_growth >= 1.0) ||
      !(options.max_shrink >= 1.0))
    throw InputError(fmt::format(
        "arc-length method: need a non-zero initial load increment (got {}), "
        "desired_iterations >= 1 (got {}), max_growth >= 1 and max_shrink >= 1 (got {}, {})",
        options.initial_load_increment, options.desired_iterations, options.max_growth, options.max_shrink));
  const double first_sign = options.initial_load_increment > 0.0 ? 1.0 : -1.0;
  if (arc_length_ <= 0.0) {
    // Δl of the first step: the tangent displacement of the initial load increment.
    Eigen::VectorXd g, q;
    double force_scale = 0.0;
    if (!assemble_system(load_factor_, g, q, force_scale))
      throw SolverError("arc-length method: the start state is not admissible (det A <= 0)");
    tangent_kept_ = false;
    if (!linear_solver_.solve(K_, q))
      throw SolverError("arc-length method: the tangent at the start state is singular");
    initial_arc_length_ = std::abs(options.initial_load_increment) * std::sqrt(position_dot(q, q));
    if (!(initial_arc_length_ > 0.0))
      throw InputError("arc-length method: the loads move no free position dof; check loads and supports");
    arc_length_ = initial_arc_length_;
  }
  const double max_arc = initial_arc_length_ * options.max_growth, min_arc = initial_arc_length_ / options.max_shrink;
  std::vector<LoadStep> steps;
  for (int s = 1; s <= max_steps; ++s) {
    int cutbacks = 0;
    int its = arc_length_step(arc_length_, first_sign);
    while (its < 0) {
      if (++cutbacks > options_.max_cutbacks)
        throw SolverError(fmt::format(
            "shell statics: arc-length step {} from load factor {:.6g} did not converge after {} cut-backs (arc "
            "length {:.3g}); use a smaller initial_load_increment or check supports and loads",
            s, load_factor_, options_.max_cutbacks, arc_length_));
      arc_length_ *= 0.5;
      its = arc_length_step(arc_length_, first_sign);
    }
    steps.push_back({load_factor_, its, arc_length_});
    // Next Δl from the effort of this step (Crisfield: Δl ∝ sqrt(desired / actual)).
    const double scaled = arc_length_ * std::sqrt(static_cast<double>(options.desired_iterations) / its);
    arc_length_ = cutbacks > 0 ? std::min(scaled, arc_length_) : std::clamp(scaled, min_arc, max_arc);
    if (on_step && !on_step(steps.back())) break;
  }
  return steps;
}

}  // namespace shellflow::shell
