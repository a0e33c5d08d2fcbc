#pragma once
// The partitioned fluid–shell driver (coupling.md, time stepping): per shell step
//   1. the shell's point pressures from the loads of t_i (or their linear prediction
//      2 F(t_i) - F(t_i-1), coupling.predictor: linear), the cavity pressure being a
//      follower pressure of the shell model evaluated at the scheme's own time;
//   2. one Newmark step of the shell (Newton inside);
//   3. the Hermite window of the step handed to the aerodynamic model, which advances the
//      flow to t_i+1 (sub-cycled, mesh moved through the space mesh);
//   4. the loads of t_i+1 from the flow at the shell's load points.
// step() is a loop over coupling iterations (coupling_iterations.h). One iteration is the
// conventional serial staggered scheme; with coupling.iterations > 1 steps 1-4 repeat from
// the start of the step (the shell rewound keeping its iteration matrix, the flow, fluid
// mesh and space mesh from an in-memory mark) with the loads the acceleration chooses, until
// the loads of t_i+1 match those applied (the implicit scheme).
//
// `monolithic` (piston theory only): the aerodynamic operator is inside the shell's Newton
// iteration (NewmarkSolver::set_linear_load), no loads are exchanged: the reference the
// staggered scheme is measured against.
#include <span>
#include <vector>

#include "shellflow/coupling/aerodynamics.h"
#include "shellflow/coupling/coupling_iterations.h"
#include "shellflow/coupling/load_point_basis.h"
#include "shellflow/coupling/shell_motion.h"
#include "shellflow/shell/newmark_solver.h"
#include "shellflow/shell/shell_model.h"

namespace shellflow::coupling {

struct PartitionedOptions {
  LoadPredictor predictor = LoadPredictor::linear;
  bool monolithic = false;
  CouplingIterationOptions iterations;  ///< max 1: explicit staggered
};

struct CouplingStepReport {
  double time = 0.0;
  int newton_iterations = 0;
  int coupling_iterations = 0;
  double coupling_residual = 0.0;  ///< relative weighted load residual of the last iteration
  FlowStepReport flow;
  double shell_seconds = 0.0;       ///< wall time of the shell step(s)
  double transfer_seconds = 0.0;    ///< wall time of the load transfer and the force balance
  double iteration_seconds = 0.0;   ///< wall time of the coupling iterations' own work (flow mark
                                    ///< and rewinds, shell rewinds, acceleration)
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
  /// a solver fails, when the coupling iterations do not converge, or when the loads are no
  /// longer finite; the solvers are then back at the start of the step.
  CouplingStepReport step(double dt);

  double time() const { return shell_.time(); }
  /// Pressure rise over the reference at the load points at time() (the loads of t_i).
  std::span<const double> pressure_rise() const { return std::span(current_).first(point_pressure_.size()); }
  /// The exchanged loads of t_i: the pressure rise at the n load points, then (a no-slip
  /// wet wall of a viscous flow) the shear -tau n of each, 3 components per point.
  std::span<const double> loads() const { return current_; }
  /// Resultant of the loads on the shell: sum_k (-sign_k dp_k) a_k, a_k = w_k x_1 x x_2 the
  /// load point's current area vector, plus (loads of size 4n) sum_k t_k |a_k| with the shear
  /// t_k (per current area, as the fluid gives it).
  Vec3 shell_side_force(std::span<const double> loads) const;
  const PartitionedOptions& options() const { return options_; }

  /// Checkpoint of the coupled state (core/archive.h): the shell solver (with its kept
  /// iteration matrix), the aerodynamic model (flow, fluid mesh, mover), the loads of
  /// the last two steps (the predictor's history) and the acceleration's history. restore()
  /// also puts the shell motion's window at the restored state.
  void save(ArchiveWriter& out) const;
  void restore(ArchiveReader& in);

 private:
  void apply_loads(std::span<const double> loads);
  /// The flow's loads at the current time (pressure rise, and shear when there is) into `loads`.
  void collect_loads(std::span<double> loads);
  /// |x_1 x x_2| / |X_1 x X_2| at load point k: current over reference area.
  double area_ratio(std::size_t k) const;
  /// The first guess of the loads of the step's end: the predictor's.
  void predict();
  /// Back to the start of the step after a failed iteration, then throws SolverError.
  [[noreturn]] void fail(const shell::NewmarkState& start, const std::string& why);

  shell::ShellModel& model_;
  shell::NewmarkSolver& shell_;
  AerodynamicModel& flow_;
  ShellStepMotion& motion_;
  PartitionedOptions options_;
  std::vector<double> current_, previous_, next_, guess_, point_pressure_;
  std::vector<Vec3> point_shear_;           ///< empty without shear
  std::vector<double> reference_jacobian_;  ///< |X_1 x X_2| per load point (with shear only)
  bool has_previous_ = false;
  LoadPointBasis basis_;  ///< for the force balance in the current configuration
  CouplingIterations iterations_;
};

}  // namespace shellflow::coupling
