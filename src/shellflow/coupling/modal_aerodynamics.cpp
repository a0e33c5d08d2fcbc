#include "shellflow/coupling/modal_aerodynamics.h"

#include <fmt/format.h>

#include <cmath>

#include "shellflow/core/error.h"
#include "shellflow/coupling/linear_flutter.h"
#include "shellflow/coupling/piston_theory.h"

namespace shellflow::coupling {

std::vector<std::complex<double>> ModalAerodynamics::roots(const LinearFlutterSystem& system,
                                                           const FlowCondition& flow) const {
  return system.eigenvalues(at(flow));
}

std::pair<std::complex<double>, Eigen::VectorXcd> ModalAerodynamics::least_stable_mode(
    const LinearFlutterSystem& system, const FlowCondition& flow) const {
  return system.least_stable_mode(at(flow));
}

PistonAerodynamics::PistonAerodynamics(const LinearFlutterSystem& system, const PistonTheory& theory) {
  shell::SparseMatrix A1, D1;
  theory.matrices(A1, D1, 1.0, 1.0);
  stiffness_ = system.generalised(A1);
  damping_ = system.generalised(D1);
}

AeroStateSpace PistonAerodynamics::at(const FlowCondition& flow) const {
  if (!(flow.mach > 1.0))
    throw_input_error("piston theory: Mach {} is not supersonic; the linear flutter analysis needs M > 1", flow.mach);
  const double m2 = flow.mach * flow.mach, beta = std::sqrt(m2 - 1.0), c = (m2 - 2.0) / (m2 - 1.0);
  return at_coefficients(flow.dynamic_pressure_over_beta, flow.damping ? flow.density * flow.speed * c / beta : 0.0);
}

AeroStateSpace PistonAerodynamics::at_coefficients(double q_stiffness, double q_damping) const {
  AeroStateSpace s;
  s.D0 = -(q_stiffness * stiffness_);
  s.D1 = -(q_damping * damping_);
  return s;
}

std::unique_ptr<ModalAerodynamics> PistonAerodynamics::truncated(int k) const {
  if (k < 1 || k > stiffness_.rows())
    throw SolverError(
        fmt::format("piston theory: cannot truncate a model of {} coordinates to {}", stiffness_.rows(), k));
  return std::unique_ptr<ModalAerodynamics>(
      new PistonAerodynamics(stiffness_.topLeftCorner(k, k), damping_.topLeftCorner(k, k)));
}

}  // namespace shellflow::coupling
