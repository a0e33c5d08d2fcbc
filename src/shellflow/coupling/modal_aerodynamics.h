#pragma once
// Linear aerodynamic models for the linear flutter analysis (docs/flutter.md, "Aerodynamic
// models"): the generalised aerodynamic forces (GAF) on the coordinates q of a
// LinearFlutterSystem (its in-vacuo modes, or the full system's mass-scaled dofs) as a
// continuous-time state-space model at a flow condition,
//   x' = A x + B0 q + B1 q',     f = C x + D0 q + D1 q',
// f the generalised force (already scaled by the flow: a model evaluated at a flow condition is
// a force, not a coefficient). The state x holds the flow's memory (lags, wave delays); a
// quasi-steady model has none (A, B0, B1, C empty). First-order piston theory is the
// quasi-steady model
//   D0 = -(rho U^2 / beta) A1,   D1 = -(rho U c / beta) D1',   c = (M^2 - 2) / (M^2 - 1),
// with A1, D1' its matrices per unit coefficient (piston_theory.h) in the system's coordinates.
// A model identified from a flow solver comes as a discrete-time model at the shell step; the
// zero-order-hold conversion to this form would delay its forces by half a step, so it has a
// discrete path of its own (discrete_flutter.h; docs/flutter.md, "Aerodynamic models").
#include <Eigen/Core>
#include <complex>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace shellflow::coupling {

class LinearFlutterSystem;
class PistonTheory;

/// The free stream a model is evaluated at. `dynamic_pressure_over_beta` is rho U^2 / beta,
/// given on its own so that a sweep in lambda = (rho U^2 / beta) a^3 / D sets it exactly.
struct FlowCondition {
  double density = 0.0;                     ///< rho_inf [kg/m^3]
  double speed = 0.0;                       ///< U [m/s]
  double mach = 0.0;                        ///< M > 1
  double dynamic_pressure_over_beta = 0.0;  ///< rho U^2 / sqrt(M^2 - 1) [Pa]
  /// false: the model's damping (its response to q') is left out: Dowell's mu/M -> 0, the
  /// classical coalescence values. A model that cannot separate it refuses this.
  bool damping = true;
};

/// The state-space GAF model at one flow condition (n = the system's size, m = states).
struct AeroStateSpace {
  Eigen::MatrixXd A;       ///< m x m
  Eigen::MatrixXd B0, B1;  ///< m x n: the states' inputs from q and q'
  Eigen::MatrixXd C;       ///< n x m
  Eigen::MatrixXd D0, D1;  ///< n x n: the direct forces from q and q'
  Eigen::Index states() const { return A.rows(); }
};

/// A provider of aerodynamic models in a LinearFlutterSystem's coordinates.
class ModalAerodynamics {
 public:
  virtual ~ModalAerodynamics() = default;
  /// The model at a flow condition. Throws InputError where the model does not apply.
  virtual AeroStateSpace at(const FlowCondition& flow) const = 0;
  /// The same model on the first k coordinates of a modal basis (the truncation check).
  virtual std::unique_ptr<ModalAerodynamics> truncated(int k) const = 0;
  /// The roots of `system` with this model at a flow condition, as LinearFlutterSystem::
  /// eigenvalues orders them; a discrete-time model solves its one-step map instead
  /// (discrete_flutter.h).
  virtual std::vector<std::complex<double>> roots(const LinearFlutterSystem& system, const FlowCondition& flow) const;
  /// The least stable root and its shape in the shell's dofs (LinearFlutterSystem::
  /// least_stable_mode).
  virtual std::pair<std::complex<double>, Eigen::VectorXcd> least_stable_mode(const LinearFlutterSystem& system,
                                                                              const FlowCondition& flow) const;
  /// A name for logs and summaries ("piston theory").
  virtual std::string name() const = 0;
};

/// First-order piston theory as a quasi-steady GAF model.
class PistonAerodynamics final : public ModalAerodynamics {
 public:
  /// The piston-theory matrices per unit coefficient in `system`'s coordinates.
  PistonAerodynamics(const LinearFlutterSystem& system, const PistonTheory& theory);
  AeroStateSpace at(const FlowCondition& flow) const override;
  /// The model at given coefficients rho U^2 / beta and rho U c / beta.
  AeroStateSpace at_coefficients(double q_stiffness, double q_damping) const;
  std::unique_ptr<ModalAerodynamics> truncated(int k) const override;
  std::string name() const override { return "piston theory"; }

 private:
  PistonAerodynamics(Eigen::MatrixXd stiffness, Eigen::MatrixXd damping)
      : stiffness_(std::move(stiffness)), damping_(std::move(damping)) {}
  Eigen::MatrixXd stiffness_, damping_;  ///< A1, D1 per unit coefficient, generalised
};

}  // namespace shellflow::coupling
