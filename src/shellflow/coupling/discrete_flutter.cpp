#include "shellflow/coupling/discrete_flutter.h"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <cmath>

#include "shellflow/core/error.h"

namespace shellflow::coupling {

Eigen::MatrixXd discrete_step_matrix(const LinearFlutterSystem& system, const DiscreteStateSpace& aero, double scale) {
  const Eigen::Index n = system.size(), m = aero.states();
  if (aero.D.rows() != n || aero.D.cols() != n || aero.B.rows() != m || aero.B.cols() != n || aero.C.rows() != n ||
      aero.C.cols() != m || aero.A.cols() != m)
    throw SolverError(
        fmt::format("discrete aerodynamic model of {} states with D {}x{} does not fit a system of size {}", m,
                    aero.D.rows(), aero.D.cols(), n));
  if (!(aero.dt > 0.0)) throw SolverError(fmt::format("discrete aerodynamic model: step {} s", aero.dt));
  // Newmark (beta 1/4, gamma 1/2) with a_n = G q_n + scale C x_n, G = -K + scale D:
  //   (I - h G) q_{n+1} = (I + h G + h scale C B) q_n + dt q'_n + h scale C (I + A) x_n,
  //   q'_{n+1} = q'_n + dt/2 (a_n + a_{n+1}),   x_{n+1} = A x_n + B q_n,   h = dt^2 / 4.
  const double dt = aero.dt, h = 0.25 * dt * dt;
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
  const Eigen::MatrixXd G = -system.stiffness() + scale * aero.D;
  const Eigen::MatrixXd sC = scale * aero.C;
  const Eigen::MatrixXd IA = Eigen::MatrixXd::Identity(m, m) + aero.A;
  Eigen::MatrixXd T = Eigen::MatrixXd::Zero(2 * n + m, 2 * n + m);
  // q_{n+1}
  Eigen::MatrixXd right(n, 2 * n + m);
  right << I + h * G + h * sC * aero.B, dt * I, h * sC * IA;
  T.topRows(n) = (I - h * G).partialPivLu().solve(right);
  // q'_{n+1}: a_n + a_{n+1} = G q_n + sC x_n + G q_{n+1} + sC (A x_n + B q_n)
  Eigen::MatrixXd accelerations(n, 2 * n + m);
  accelerations << G + sC * aero.B, Eigen::MatrixXd::Zero(n, n), sC * IA;
  accelerations += G * T.topRows(n);
  T.middleRows(n, n) = 0.5 * dt * accelerations;
  T.block(n, n, n, n) += I;
  // x_{n+1}
  T.block(2 * n, 0, m, n) = aero.B;
  T.bottomRightCorner(m, m) = aero.A;
  return T;
}

std::vector<std::complex<double>> discrete_eigenvalues(const LinearFlutterSystem& system,
                                                       const DiscreteStateSpace& aero, double scale) {
  const Eigen::EigenSolver<Eigen::MatrixXd> es(discrete_step_matrix(system, aero, scale), false);
  if (es.info() != Eigen::Success) throw SolverError("discrete flutter system: the eigenvalue solver did not converge");
  std::vector<std::complex<double>> roots;
  for (const std::complex<double>& z : es.eigenvalues())
    if (z.imag() >= 0.0 && z != 0.0) roots.push_back(std::log(z) / aero.dt);
  sort_roots(roots);
  return roots;
}

}  // namespace shellflow::coupling
