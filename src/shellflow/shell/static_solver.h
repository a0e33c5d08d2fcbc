#pragma once
// Static analysis: load stepping with Newton–Raphson on the dead loads of a ShellModel
// (shell.md §7 "Statics", §8), with step cut-back on failure; path following through limit
// points by displacement control and by the cylindrical arc-length method (Crisfield).
#include <functional>
#include <string>
#include <vector>

#include "shellflow/shell/linear_solver.h"
#include "shellflow/shell/shell_model.h"

namespace shellflow::shell {

/// Convergence criteria of shell.md §8 (defaults as there).
struct NewtonOptions {
  double tolerance = 1e-8;           ///< on increments of x (× L_ref √N), G (× √N), a (max)
  double residual_tolerance = 1e-6;  ///< on ‖g‖ relative to the force scale
  int max_iterations = 25;
  int max_cutbacks = 5;  ///< halvings of a failed increment before giving up
  /// Modified Newton (NewmarkSolver, and StaticSolver under load control): keep the
  /// factorised iteration matrix across iterations and steps / load levels, and assemble
  /// and factorise it again only when an iteration reduces the residual by less than
  /// `refresh_ratio` (that iteration is then redone with the new matrix), the step size
  /// changes, or a step fails (dynamics: retried once with a fresh matrix before it is
  /// halved). The converged states meet the same tests; an iteration costs an
  /// internal-force assembly and a solve instead of a tangent assembly and a factorisation.
  bool modified = false;
  double refresh_ratio = 0.5;
};

/// Result of one converged load level.
struct LoadStep {
  double load_factor = 0.0;
  int iterations = 0;
  double arc_length = 0.0;  ///< arc length of the step (arc-length method only, else 0)
};

/// The displacement component that displacement control prescribes: of one node, or the
/// mean over the nodes of a physical group (e.g. a loaded edge).
struct ControlledDisplacement {
  Index node = -1;    ///< node index; -1 to use `group`
  std::string group;  ///< group whose mean displacement is controlled (when node < 0)
  int component = 2;  ///< global axis 0, 1, 2
};

/// Cylindrical arc-length method (Crisfield 1981): the step length Δl bounds the position
/// increment of the step, ‖Δx‖ = Δl over the free position dofs (directors and `a` are left
/// out so that the norm has one unit, length).
struct ArcLengthOptions {
  /// Load-factor increment of the first step's tangent predictor; fixes the initial Δl.
  /// Its sign gives the initial direction.
  double initial_load_increment = 0.1;
  /// Δl of the next step = Δl · sqrt(desired / iterations of the last step).
  int desired_iterations = 5;
  /// Δl stays within [initial / max_shrink, initial · max_growth] except for cut-backs.
  double max_growth = 4.0;
  double max_shrink = 16.0;
};

/// Called after every converged point of a path-following run; return false to stop.
using PathCallback = std::function<bool(const LoadStep&)>;

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

  /// Current value of a controlled displacement component. Throws InputError for a bad
  /// node, group or component.
  double controlled_displacement(const ControlledDisplacement& control) const;
  /// Newton with the load factor as extra unknown and the controlled displacement held at
  /// `value` (bordered solve: K δu_r = -g, K δu_t = q, δλ from the constraint). Returns the
  /// iterations, or -1 (state restored) when it does not converge or the control stops
  /// moving with the load (a displacement limit point).
  int solve_displacement(const ControlledDisplacement& control, double value);
  /// Displacement control: moves the controlled displacement from its current value to
  /// `final_value` in `num_steps` equal increments (halved on failure, as in `run`), the
  /// load factor following. Passes load limit points (not displacement limit points:
  /// snap-back needs `run_arc_length`). Throws SolverError when the cut-backs are exhausted.
  std::vector<LoadStep> run_displacement_control(const ControlledDisplacement& control, int num_steps,
                                                 double final_value,
                                                 const std::function<void(const LoadStep&)>& on_step = {});

  /// Cylindrical arc-length method from the current state: tangent predictor with the sign
  /// of the previous step's increment (no doubling back), corrector iterations on the
  /// quadratic constraint taking the root whose increment is closest in direction to the
  /// current one, Δl adapted to the iteration count and halved when a step fails (no
  /// convergence, complex roots, inadmissible state) up to max_cutbacks times in a row, then
  /// SolverError. Runs `max_steps` converged steps unless `on_step` returns false first.
  /// Consecutive calls continue the path (Δl and direction are kept).
  std::vector<LoadStep> run_arc_length(int max_steps, const ArcLengthOptions& options,
                                       const PathCallback& on_step = {});

  /// Sets the current state (increments u and load factor), e.g. to prescribe support
  /// displacements: the components a support fixes keep the values set here in every
  /// solve (those of a ShellModel prescribed motion take its values at each load level).
  /// Forgets the direction of the last arc-length step.
  void set_state(const Eigen::VectorXd& u, double load_factor);

  const Eigen::VectorXd& displacement() const { return u_; }
  double load_factor() const { return load_factor_; }
  const ShellModel& model() const { return model_; }
  /// ∂F_ext/∂λ at the current state: dead loads plus follower loads at factor 1, pressure
  /// histories through their derivative at λ (the load factor is their pseudo-time); the
  /// model's point loads do not depend on λ (they act as set at every level).
  Eigen::VectorXd load_direction() const;
  /// Free-dof norm of F_int - F_ext at the current state and load factor, relative to
  /// max(‖F_ext‖, ‖F_int‖) (the §8 residual measure). +inf for an inadmissible state.
  double relative_residual() const;

 private:
  /// Assembles K (with the follower load stiffness), the residual g = F_int - F_ext and the
  /// load direction q at (u_, load_factor). False for an inadmissible state.
  bool assemble_system(double load_factor, Eigen::VectorXd& residual, Eigen::VectorXd& direction, double& force_scale);
  /// Moves the prescribed dofs to their values at `load_factor` with a linear predictor
  /// for the free dofs; false when the tangent is singular or the state inadmissible.
  bool predict_prescribed(double load_factor);
  /// Solves K δu_r = -g and K δu_t = q with the tangent of the last assemble_system.
  bool solve_pair(Eigen::VectorXd& minus_g_then_du_r, Eigen::VectorXd& q_then_du_t);
  Eigen::VectorXd control_weights(const ControlledDisplacement& control) const;
  double position_dot(const Eigen::VectorXd& a, const Eigen::VectorXd& b) const;
  /// One arc-length step of length `arc_length` from the current state; iterations or -1
  /// (state restored).
  int arc_length_step(double arc_length, double direction_sign);

  const ShellModel& model_;
  NewtonOptions options_;
  Eigen::VectorXd u_;
  double load_factor_ = 0.0;
  SparseMatrix K_;
  Eigen::VectorXd f_int_;
  ShellSystemSolver linear_solver_;
  /// Modified Newton: linear_solver_ holds a factorised tangent that solve() may reuse.
  bool tangent_kept_ = false;
  /// Arc-length state kept between calls: last converged increment and Δl.
  Eigen::VectorXd last_increment_;
  double arc_length_ = 0.0;
  double initial_arc_length_ = 0.0;
};

/// The convergence test of shell.md §8 on one Newton correction `du` and residual `g` (free
/// dofs only). `force_scale` is max(‖F_ext‖, ‖F_int‖, ‖M ÿ‖) on free dofs. Positions are
/// scaled by the bounding-box diagonal, not by the norm of the initial positions as in O2P2,
/// which would depend on where the origin is (the spec's correction).
bool newton_converged(const ShellModel& model, const NewtonOptions& options, const Eigen::VectorXd& du,
                      const Eigen::VectorXd& g, double force_scale);

}  // namespace shellflow::shell
