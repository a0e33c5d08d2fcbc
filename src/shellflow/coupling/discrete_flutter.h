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

/// An identified discrete-time GAF model (inputs [q; q']) as a provider of the flutter
/// analysis (sweep_flutter). At another flow condition it is scaled as a model of the reduced
/// time t U / a: the forces by (rho U^2 / beta) over the identification's (the 1/beta
/// scaling of ../design/identified_aero.md, exact in density), the step by U0 / U and the q'
/// inputs' columns by U0 / U. The structure is then discretised at that step.
class IdentifiedAerodynamics final : public ModalAerodynamics {
 public:
  /// `identified`: the free stream of the identification run. Throws InputError when the
  /// model's inputs are not twice its outputs.
  IdentifiedAerodynamics(DiscreteStateSpace model, const FlowCondition& identified, DiscreteCoupling coupling);
  /// Throws InputError: the model has no continuous-time form.
  AeroStateSpace at(const FlowCondition& flow) const override;
  std::vector<std::complex<double>> roots(const LinearFlutterSystem& system, const FlowCondition& flow) const override;
  std::pair<std::complex<double>, Eigen::VectorXcd> least_stable_mode(const LinearFlutterSystem& system,
                                                                      const FlowCondition& flow) const override;
  std::unique_ptr<ModalAerodynamics> truncated(int k) const override;
  std::string name() const override { return "identified"; }
  /// The model at `flow` and its force scale.
  DiscreteStateSpace scaled(const FlowCondition& flow, double& scale) const;

 private:
  DiscreteStateSpace model_;
  FlowCondition identified_;
  DiscreteCoupling coupling_;
};

}  // namespace shellflow::coupling
