#pragma once
// The aerodynamic load models behind one interface (coupling.md): what the partitioned
// driver asks of "the flow" in a shell step. Two models:
//   - FlowModel  (flow.h): the Euler/Navier–Stokes flow on the fluid mesh, moved through the
//     space mesh, sub-cycled inside the shell step (also without a flow: the mesh-motion tests);
//   - PistonLoads (below): first-order piston theory from the shell's own motion.
#include <Eigen/Core>
#include <algorithm>
#include <optional>
#include <span>
#include <string>

#include "shellflow/core/archive.h"
#include "shellflow/coupling/piston_theory.h"
#include "shellflow/coupling/shell_motion.h"

namespace shellflow::coupling {

/// What one shell step cost the flow.
struct FlowStepReport {
  int substeps = 0;            ///< fluid (or fluid-mesh) steps in the shell step
  double stable_substeps = 0;  ///< the sub-steps stability asked for (auto: before rounding up)
  double mesh_seconds = 0.0;   ///< wall time of the mesh motion (space mesh, fluid nodes, wall velocity)
  double flow_seconds = 0.0;   ///< wall time of the flow steps (and the stability check)
};

class AerodynamicModel {
 public:
  virtual ~AerodynamicModel() = default;
  virtual std::string name() const = 0;
  /// Advances the flow from its time to `t_end`, the end of the shell step whose motion
  /// `motion` holds (its window). Throws SolverError naming the time on failure; the model
  /// then keeps its last valid state.
  virtual FlowStepReport advance(const ShellStepMotion& motion, double t_end) = 0;
  /// Pressure rise over the reference pressure at every shell load point, at the current
  /// time; (u, v) is the shell state at that time.
  virtual void pressure_rise(const Eigen::VectorXd& u, const Eigen::VectorXd& v, std::span<double> dp) = 0;
  /// Per load point: +1 where the shell normal (like V) points into the flow.
  virtual std::span<const double> sign() const = 0;
  /// True when the wet wall takes the gas's shear too (a no-slip wet wall of a viscous flow,
  /// paper eq. 30): shear() then gives it, and the driver passes it to the shell.
  virtual bool has_shear() const { return false; }
  /// Viscous traction -tau n at every load point at the current time (force per area of the
  /// gas on the shell, n out of the fluid, global axes); zero without shear.
  virtual void shear(std::span<Vec3> out) { std::fill(out.begin(), out.end(), Vec3::Zero()); }
  /// Force of the gas (pressure minus the reference pressure) on the wet boundary from the
  /// fluid side, when the model has a fluid mesh.
  virtual std::optional<Vec3> fluid_side_force() const { return std::nullopt; }
  /// Checkpoint of the model's state (core/archive.h); piston theory has none.
  virtual void save(ArchiveWriter&) const {}
  virtual void restore(ArchiveReader&) {}

  /// An in-memory mark of the state (the coupling iterations' start of the step), and the
  /// way back to it, exact: the checkpoint's save/restore into memory (save_mark /
  /// restore_mark; a distributed flow keeps its rank's part there, not the whole state).
  void mark() {
    ArchiveWriter out;
    save_mark(out);
    mark_ = out.bytes();
  }
  void rewind() {
    ArchiveReader in(mark_, "the coupling iterations' mark of the flow");
    restore_mark(in);
  }

 protected:
  virtual void save_mark(ArchiveWriter& out) const { save(out); }
  virtual void restore_mark(ArchiveReader& in) { restore(in); }

 private:
  std::string mark_;
};

/// Piston theory as an aerodynamic model: nothing to advance; the loads follow from the
/// shell state.
class PistonLoads final : public AerodynamicModel {
 public:
  PistonLoads(const shell::ShellModel& model, PistonTheoryFlow flow) : theory_(model, flow) {}
  std::string name() const override { return "piston_theory"; }
  FlowStepReport advance(const ShellStepMotion&, double) override { return {}; }
  void pressure_rise(const Eigen::VectorXd& u, const Eigen::VectorXd& v, std::span<double> dp) override {
    theory_.pressure_rise(u, v, dp);
  }
  std::span<const double> sign() const override { return theory_.sign(); }
  const PistonTheory& theory() const { return theory_; }

 private:
  PistonTheory theory_;
};

}  // namespace shellflow::coupling
