#pragma once
// The coupling iterations of one shell step (docs/coupling.md, "Implicit coupling"): the
// fixed point x = H(x) on the load vector, started from the load predictor, accelerated
// (acceleration.h), stopped when the weighted residual |H(x) - x| / |H(x)| is below the
// tolerance in every block of the vector (the pressure, and the shear of a viscous flow: each
// block's own relative residual, so that the shear converges as well as the pressure). With one iteration it is the
// explicit staggered scheme: no test, the residual is only reported. The loop itself is the driver's
// (PartitionedSolver::step): this object decides what to apply next and when to stop, so that the 1-D piston problem of
// the tests runs the very same decisions.
//
// And the theory of the explicit scheme's added-mass instability, for a mass m per area on
// a spring facing a gas of impedance rho c (a piston on a semi-infinite gas column):
// staggered_spectral_radius / staggered_critical_ratio.
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "shellflow/coupling/acceleration.h"

namespace shellflow::coupling {

enum class LoadPredictor { none, linear };

struct CouplingIterationOptions {
  int max_iterations = 1;   ///< per shell step (1: explicit staggered)
  double tolerance = 1e-6;  ///< of the relative weighted load residual
  AccelerationOptions acceleration;
  /// The explicit scheme's blow-up monitor takes loads of an RMS pressure below this for
  /// round-off (a flow at rest over a shell at rest), whatever they do.
  double noise_pressure = 0.0;
};

class CouplingIterations {
 public:
  enum class Outcome {
    done,           ///< converged, or the explicit scheme's single iteration
    again,          ///< apply applied() and repeat the step
    not_converged,  ///< max_iterations reached above the tolerance
    diverged,       ///< the loads are not finite, or (explicit scheme) blow up: see below
  };
  /// The explicit scheme is taken to have blown up when the predicted loads missed the
  /// flow's by more than half their size (relative residual > kBlowUpMiss) in kBlowUpMissed
  /// of the last kBlowUpWindow steps and the loads are now kBlowUpGrowth times larger than
  /// ever before those steps and above the noise (tested from step 2 kBlowUpWindow on,
  /// after the start-up): a
  /// load that jumps from step to step and grows by an order of magnitude is no motion the
  /// step resolves.
  static constexpr int kBlowUpWindow = 10, kBlowUpMissed = 7;
  static constexpr double kBlowUpMiss = 0.5;
  static constexpr double kBlowUpGrowth = 10.0;

  /// `weight`: per entry, its load point's reference area. `blocks`: the sizes of the
  /// vector's blocks in order (empty: one block).
  CouplingIterations(CouplingIterationOptions options, std::vector<double> weight,
                     std::vector<std::size_t> blocks = {});

  bool implicit() const { return options_.max_iterations > 1; }
  const CouplingIterationOptions& options() const { return options_; }
  /// A window starts from the first guess x^0.
  void begin(std::span<const double> guess);
  /// The loads to apply in the current iteration.
  std::span<const double> applied() const { return x_; }
  /// Iteration k gave H(x^k) = `result`: decides.
  Outcome result(std::span<const double> result);
  int iteration() const { return iteration_; }
  /// |H(x^k) - x^k|_w / |H(x^k)|_w of the last iteration (0 when both vanish), the largest
  /// over the blocks.
  double residual() const { return residual_; }
  /// What carries over between windows (the acceleration's history, the explicit scheme's
  /// recent residuals).
  void save(ArchiveWriter& out) const;
  void restore(ArchiveReader& in);

 private:
  struct Recent {
    double residual = 0.0, load_norm = 0.0;
  };
  Outcome explicit_step(double load_norm);

  CouplingIterationOptions options_;
  std::vector<double> weight_, x_, difference_;
  std::vector<std::size_t> blocks_;  ///< never empty: one block of the whole vector at least
  double noise_norm_ = 0.0;          ///< options_.noise_pressure in the weighted norm
  std::unique_ptr<Acceleration> acceleration_;
  int iteration_ = 0;
  double residual_ = 0.0;
  std::int64_t steps_ = 0;                      ///< explicit steps taken
  double earlier_peak_ = 0.0;                   ///< the largest load norm before the recent steps
  std::array<Recent, kBlowUpWindow> recent_{};  ///< oldest first
};

/// Spectral radius of one step of the explicit staggered scheme (Newmark trapezoidal rule,
/// loads of the step's end taken from the last step, or linearly extrapolated) for
/// m x'' + k x = -rho c x', with ratio = rho c dt / m and omega_dt = sqrt(k/m) dt.
double staggered_spectral_radius(double ratio, double omega_dt, LoadPredictor predictor);
/// The largest ratio rho c dt / m at which that radius stays <= 1 (bisection; for
/// omega_dt -> 0: 2 without predictor, 2/sqrt(3) with the linear one). For omega_dt >= 2
/// (modes the step does not resolve) the scheme is weakly unstable at every ratio: returns 0.
double staggered_critical_ratio(LoadPredictor predictor, double omega_dt = 0.0);

}  // namespace shellflow::coupling
