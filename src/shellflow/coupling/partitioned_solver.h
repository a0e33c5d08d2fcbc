#pragma once
// The partitioned fluid–shell driver (coupling.md, time stepping): per shell step
//   1. the shell's point pressures from the loads of t_i (or their linear prediction
//      2 F(t_i) - F(t_i-1), coupling.predictor: linear), the cavity pressure being a
//      follower pressure of the shell model evaluated at the scheme's own time;
//   2. one Newmark step of the shell (Newton inside);
//   3. the Hermite window of the step handed to the aerodynamic model, which advances the
//      flow to t_i+1 (sub-cycled, mesh moved through the space mesh);
//   4. the loads of t_i+1 from the flow at the shell's load points.
// step() is a loop over coupling iterations (one iteration: the conventional serial
// staggered scheme), on top of the solvers' exact state save/restore, so that an implicit
// variant with Aitken / IQN-ILS relaxation adds an acceleration class, not a reshaping.
//
// `monolithic` (piston theory only): the aerodynamic operator is inside the shell's Newton
// iteration (NewmarkSolver::set_linear_load), no loads are exchanged: the reference the
// staggered scheme is measured against.
#include <span>
#include <vector>

#include "shellflow/coupling/aerodynamics.h"
#include "shellflow/coupling/load_point_basis.h"
#include "shellflow/coupling/shell_motion.h"
#include "shellflow/shell/newmark_solver.h"
#include "shellflow/shell/shell_model.h"

namespace shellflow::coupling {

enum class LoadPredictor { none, linear };

struct PartitionedOptions {
  LoadPredictor predictor = LoadPredictor::linear;
  bool monolithic = false;
  int max_iterations = 1;  ///< coupling iterations per step (1: explicit staggered)
};

struct CouplingStepReport {
  double time = 0.0;
  int newton_iterations = 0;
  int coupling_iterations = 0;
  FlowStepReport flow;
  double shell_seconds = 0.0;       ///< wall time of the shell step(s)
  double transfer_seconds = 0.0;    ///< wall time of the load transfer and the force balance
  Vec3 shell_force = Vec3::Zero();  ///< resultant of the exchanged pressure on the shell
  std::optional<Vec3> fluid_force;  ///< the same from the fluid side (when there is a mesh)
};

class PartitionedSolver {
 public:
  /// The shell solver must hold its initial state (set_initial_state) and the flow its
  /// initial state at the same time. The model is the one the solver was built on: the
  /// driver changes its point pressures between steps. The constructor applies the loads of
  /// the initial time and has the shell recompute its initial acceleration with them.
  PartitionedSolver(shell::ShellModel& model, shell::NewmarkSolver& shell, AerodynamicModel& flow,
                    ShellStepMotion& motion, PartitionedOptions options);

  /// Advances shell and flow by one shell step dt. Throws SolverError (naming the time) when
  /// a solver fails; the solvers keep their last valid states.
  CouplingStepReport step(double dt);

  double time() const { return shell_.time(); }
  /// Pressure rise over the reference at the load points at time() (the loads of t_i).
  std::span<const double> pressure_rise() const { return current_; }
  /// Resultant of the pressure rise dp on the shell in its current configuration:
  /// sum_k (-sign_k dp_k) a_k, a_k = w_k x_1 x x_2 the load point's current area vector.
  Vec3 shell_side_force(std::span<const double> dp) const;
  const PartitionedOptions& options() const { return options_; }

  /// Checkpoint of the coupled state (core/archive.h): the shell solver (with its kept
  /// iteration matrix), the aerodynamic model (flow, fluid mesh, mover) and the loads of
  /// the last two steps (the predictor's history). restore() also puts the shell motion's
  /// window at the restored state.
  void save(ArchiveWriter& out) const;
  void restore(ArchiveReader& in);

 private:
  void apply_loads();

  shell::ShellModel& model_;
  shell::NewmarkSolver& shell_;
  AerodynamicModel& flow_;
  ShellStepMotion& motion_;
  PartitionedOptions options_;
  std::vector<double> current_, previous_, next_, applied_, point_pressure_;
  bool has_previous_ = false;
  LoadPointBasis basis_;  ///< for the force balance in the current configuration
};

}  // namespace shellflow::coupling
