#pragma once
// The forced-motion identification run's coupling side (docs/flutter.md, "Identified
// aerodynamics"; ../design/identified_aero.md): the wall follows prescribed motions of the
// shell's in-vacuo modes, u(t) = sum_j q_j(t) phi_j, through the coupled run's own path — the
// Hermite window of one shell step handed to the aerodynamic model (sub-cycling, mesh motion,
// wall velocities as in a coupled run), the loads of the step's end read at the shell's load
// points — and no shell is solved. Each step records the modal coordinates q_n, q'_n of t_n
// and the generalised forces
//   f_i(t_n) = sum_k phi_i(x_k) . (-sign_k dp_k) a_k,   a_k = w_k X_1 x X_2 (reference),
// the same force the partitioned driver applies, projected on the modes in the flat reference
// (the linearisation of the follower pressure). f_n is what the coupled run's shell would feel
// at t_n: motion and load samples share their time stamps.
//
// The motion: one raised-cosine pulse per mode, q_j(t) = A_j (1 - cos(2 pi (t - t_j) / w)) / 2
// on [t_j, t_j + w], t_j = j (w + gap), then `gap` of rest; A_j gives mode j a peak mid-surface
// deflection `amplitude`. Then K velocity pulses, q_j = 0 and q'_j = (pi A_j / w) (1 - cos ...) / 2
// at the step ends: the wall moves inside each step's Hermite window only. A smooth motion
// has q' = dq/dt, which leaves the split of the response between the q and q' taps
// undetermined (a 24-tap fit of the strip determines 240 of its 288 taps per force); the
// velocity pulses determine it.
#include <Eigen/Core>
#include <span>
#include <vector>

#include "shellflow/core/archive.h"
#include "shellflow/coupling/aerodynamics.h"
#include "shellflow/coupling/shell_motion.h"
#include "shellflow/shell/shell_model.h"

namespace shellflow::coupling {

struct ModalPulses {
  double width = 0.0;        ///< w [s]
  double gap = 0.0;          ///< rest between pulses and after the last [s]
  std::vector<double> peak;  ///< A_j per mode
  /// Pulse p: of displacement for p < K, of velocity alone for K <= p < 2 K.
  double start(int p) const { return p * (width + gap); }
  double end() const { return 2.0 * double(peak.size()) * (width + gap); }
  double q(int j, double t) const;
  double dq(int j, double t) const;

 private:
  double shape(int p, double t) const;  ///< (1 - cos(2 pi s)) / 2 on the pulse, else 0
};

/// The record of a forced-motion run, one row per shell step from t = 0.
struct ForcedMotionRecord {
  double dt = 0.0;
  std::vector<double> time;
  std::vector<Eigen::VectorXd> inputs;  ///< [q; q'] (2 K)
  std::vector<Eigen::VectorXd> forces;  ///< f (K)
  /// The record as matrices (rows = samples): inputs N x 2K, forces N x K.
  Eigen::MatrixXd input_matrix() const;
  Eigen::MatrixXd force_matrix() const;
};

class ForcedModalMotion {
 public:
  /// `modes`: the in-vacuo modes in the shell's dofs, one column each; `amplitude`: the peak
  /// deflection of each pulse [m]. Records sample 0 (the flow's loads at rest).
  ForcedModalMotion(const shell::ShellModel& model, const Eigen::MatrixXd& modes, double width, double gap,
                    double amplitude, double dt, AerodynamicModel& flow, ShellStepMotion& motion);

  /// One shell step: the window [t_n, t_n+1] of the prescribed motion to the flow, which
  /// advances; the sample of t_n+1 appended. Throws the flow's SolverError.
  FlowStepReport step();
  long steps() const { return long(record_.time.size()) - 1; }
  /// The steps that cover every pulse and the rest after the last.
  long total_steps() const;
  double time() const { return record_.time.back(); }
  const ForcedMotionRecord& record() const { return record_; }
  const ModalPulses& pulses() const { return pulses_; }
  /// The generalised forces of pressure rises dp at the load points (the matrix's product).
  Eigen::VectorXd modal_forces(std::span<const double> dp) const;

  /// The flow and the record (core/archive.h); restore puts the window at the restored time.
  void save(ArchiveWriter& out) const;
  void restore(ArchiveReader& in);

 private:
  /// [q; q'] of the pulses at t.
  Eigen::VectorXd modal_state(double t) const;
  /// Shell displacement and velocity at t.
  void shell_state(double t, Eigen::VectorXd& u, Eigen::VectorXd& v) const;
  void sample_at(double t);

  Eigen::MatrixXd modes_;
  ModalPulses pulses_;
  double dt_;
  AerodynamicModel& flow_;
  ShellStepMotion& motion_;
  Eigen::MatrixXd load_;  ///< K x n: f = load_ (-sign dp)
  std::vector<double> dp_;
  ForcedMotionRecord record_;
};

}  // namespace shellflow::coupling
