#pragma once
// The linear flutter analysis with a discrete-time aerodynamic model (an identified GAF,
// gaf_identification.h): the coupled system advanced by one shell step,
//   structure  M q'' + K q = f  by Newmark's average acceleration at the model's step dt
//              (the scheme of every shellflow shell run, M -> I in the system's coordinates),
//   flow       x_{n+1} = A x_n + B u_n,   f_n = scale (C x_n + D u_n),
// the model's input u_n being q_n, or [q_n; q'_n] (a model identified from the flow's forced
// motion: the wall moves by the cubic Hermite window of q and q' at both ends of the step, so
// the flow's response is a linear function of both sequences), is the linear map
// Y_{n+1} = T Y_n. Its eigenvalues z give the roots s = ln(z) / dt; the panel flutters when
// some |z| > 1. Unlike a conversion of the model to continuous time (which would delay its
// forces by half a step, ../design/identified_aero.md), the model meets the structure with the
// sampling it was identified with. `scale` multiplies the forces: rho U^2 / beta over the
// identification's, exact for a density (lambda) sweep at the identification's Mach number.
//
// Two couplings of the two (docs/flutter.md, "Identified aerodynamics"):
//   simultaneous  the force of t_{n+1} enters the step to t_{n+1} (a monolithic solve);
//   staggered     the step to t_{n+1} takes the linear prediction 2 f_n - f_{n-1}, as the
//                 partitioned driver's explicit scheme does (coupling.predictor: linear):
//                 Y = [q; q'; q''; x; f_{n-1}].
#include <complex>
#include <memory>
#include <vector>

#include "shellflow/coupling/gaf_identification.h"
#include "shellflow/coupling/linear_flutter.h"
#include "shellflow/coupling/modal_aerodynamics.h"

namespace shellflow::coupling {

enum class DiscreteCoupling { simultaneous, staggered };

/// T: the one-step map (2 n + states wide, simultaneous; 4 n + states, staggered). Throws
/// SolverError when the model's sizes fit neither input form or its step is not positive.
Eigen::MatrixXd discrete_step_matrix(const LinearFlutterSystem& system, const DiscreteStateSpace& aero, double scale,
                                     DiscreteCoupling coupling = DiscreteCoupling::simultaneous);

/// The roots s = ln(z) / dt with Im s >= 0 of T's eigenvalues z != 0, ordered by Im s, then
/// Re s (a z on the negative real axis gives Im s = pi / dt).
std::vector<std::complex<double>> discrete_eigenvalues(const LinearFlutterSystem& system,
                                                       const DiscreteStateSpace& aero, double scale,
                                                       DiscreteCoupling coupling = DiscreteCoupling::simultaneous);

/// A discrete-time GAF model (inputs [q; q']) as a provider of the flutter analysis
/// (sweep_flutter): the roots come from the one-step map of the model at each flow condition.
class DiscreteAerodynamics : public ModalAerodynamics {
 public:
  explicit DiscreteAerodynamics(DiscreteCoupling coupling) : coupling_(coupling) {}
  /// Throws InputError: the model has no continuous-time form.
  AeroStateSpace at(const FlowCondition& flow) const override;
  std::vector<std::complex<double>> roots(const LinearFlutterSystem& system, const FlowCondition& flow) const override;
  std::pair<std::complex<double>, Eigen::VectorXcd> least_stable_mode(const LinearFlutterSystem& system,
                                                                      const FlowCondition& flow) const override;
  /// The model at `flow` and its force scale. Throws InputError for a flow without damping
  /// (the forces cannot be split) or one that is not supersonic.
  virtual DiscreteStateSpace scaled(const FlowCondition& flow, double& scale) const = 0;

 protected:
  DiscreteCoupling coupling_;
};

/// An identified discrete-time GAF model from one identification. At another flow condition
/// it is scaled as a model of the reduced time t U / a: the forces by (rho U^2 / beta) over the
/// identification's (the 1/beta scaling of ../design/identified_aero.md, exact in density), the
/// step by U0 / U and the q' inputs' columns by U0 / U. The structure is then discretised at
/// that step.
class IdentifiedAerodynamics final : public DiscreteAerodynamics {
 public:
  /// `identified`: the free stream of the identification run. Throws InputError when the
  /// model's inputs are not twice its outputs.
  IdentifiedAerodynamics(DiscreteStateSpace model, const FlowCondition& identified, DiscreteCoupling coupling);
  std::unique_ptr<ModalAerodynamics> truncated(int k) const override;
  std::string name() const override { return "identified"; }
  DiscreteStateSpace scaled(const FlowCondition& flow, double& scale) const override;

 private:
  DiscreteStateSpace model_;
  FlowCondition identified_;
};

/// Two FIR models identified at Mach numbers M1 < M2 (the same density, pressure and step).
/// Between them the taps are interpolated linearly in Mach at the acoustic time t c / a:
///   H_j = sum_i w_i s_i [Hq_ij, (U_i / U) Hv_ij],   w_1 = (M2 - M) / (M2 - M1), w_2 = 1 - w_1,
/// s_i = (rho U^2 / beta) over identification i's, at the step dt c_id / c; each model's
/// velocity inputs so carry the 1 / U of a reduced velocity. At M1 and M2 it is that
/// identification's model (IdentifiedAerodynamics); outside [M1, M2] the nearer one, scaled in
/// reduced time. Piston theory so interpolated is piston theory with its damping factor
/// c(M) = (M^2 - 2) / (M^2 - 1) interpolated linearly between M1 and M2.
class MachInterpolatedAerodynamics final : public DiscreteAerodynamics {
 public:
  /// Throws InputError when the Mach numbers are not increasing, the models' steps, sizes or
  /// sound speeds differ, or a model's inputs are not [q; q'].
  MachInterpolatedAerodynamics(FirModel low, const FlowCondition& at_low, FirModel high, const FlowCondition& at_high,
                               DiscreteCoupling coupling);
  std::unique_ptr<ModalAerodynamics> truncated(int k) const override;
  std::string name() const override { return "identified at two Mach numbers"; }
  DiscreteStateSpace scaled(const FlowCondition& flow, double& scale) const override;

 private:
  FirModel models_[2];
  FlowCondition flows_[2];
  IdentifiedAerodynamics ends_[2];
};

/// The first k coordinates of a model of inputs [q; q'] (forces, q and q' taps).
FirModel truncated_fir(const FirModel& model, int k);

}  // namespace shellflow::coupling
