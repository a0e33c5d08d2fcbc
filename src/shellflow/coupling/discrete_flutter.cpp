#include "shellflow/coupling/discrete_flutter.h"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <cmath>

#include "shellflow/core/error.h"

namespace shellflow::coupling {

namespace {

using Eigen::MatrixXd;

/// The model's input blocks: D = [Dq Dv], B = [Bq Bv] (Dv, Bv zero for inputs q alone).
struct InputBlocks {
  MatrixXd Dq, Dv, Bq, Bv;
};

InputBlocks input_blocks(const LinearFlutterSystem& system, const DiscreteStateSpace& aero) {
  const Eigen::Index n = system.size(), m = aero.states(), inputs = aero.D.cols();
  if (aero.D.rows() != n || (inputs != n && inputs != 2 * n) || aero.B.rows() != m || aero.B.cols() != inputs ||
      aero.C.rows() != n || aero.C.cols() != m || aero.A.cols() != m)
    throw SolverError(
        fmt::format("discrete aerodynamic model of {} states with D {}x{} does not fit a system of size {} (inputs q "
                    "or [q; q'])",
                    m, aero.D.rows(), aero.D.cols(), n));
  if (!(aero.dt > 0.0)) throw SolverError(fmt::format("discrete aerodynamic model: step {} s", aero.dt));
  InputBlocks b;
  b.Dq = aero.D.leftCols(n);
  b.Bq = aero.B.leftCols(n);
  b.Dv = inputs == n ? MatrixXd::Zero(n, n) : MatrixXd(aero.D.rightCols(n));
  b.Bv = inputs == n ? MatrixXd::Zero(m, n) : MatrixXd(aero.B.rightCols(n));
  return b;
}

/// Newmark (beta 1/4, gamma 1/2) with the force of the step's end,
///   a = G q + E q' + s C x,   G = -K + s Dq,   E = s Dv,   x_{n+1} = A x_n + Bq q_n + Bv q'_n,
/// on Y = [q; q'; x], with p = a_n + s C x_{n+1} (known at the step's start), h = dt^2 / 4:
///   q'_{n+1} = W (q'_n + dt/2 (p + G q_{n+1})),   W = (I - dt/2 E)^-1,
///   (I - h G - h dt/2 E W G) q_{n+1} = q_n + dt q'_n + h p + h E W (q'_n + dt/2 p).
/// The velocity is eliminated first: a solve of the coupled 2n system would pivot on the
/// large dt/2 G rows and lose the roots' round-off near a coalescence.
MatrixXd simultaneous(const LinearFlutterSystem& system, const DiscreteStateSpace& aero, const InputBlocks& b,
                      double s) {
  const Eigen::Index n = system.size(), m = aero.states(), N = 2 * n + m;
  const double dt = aero.dt, h = 0.25 * dt * dt;
  const MatrixXd I = MatrixXd::Identity(n, n);
  const MatrixXd G = -system.stiffness() + s * b.Dq, E = s * b.Dv, sC = s * aero.C;
  MatrixXd next_x(m, N);  // x_{n+1} of Y_n
  next_x << b.Bq, b.Bv, aero.A;
  MatrixXd push(n, N);  // p = a_n + s C x_{n+1}
  push << G, E, sC;
  push += sC * next_x;
  MatrixXd velocity = 0.5 * dt * push;  // q'_n + dt/2 p
  velocity.middleCols(n, n) += I;
  const bool damped = E.squaredNorm() > 0.0;
  const Eigen::PartialPivLU<MatrixXd> W(I - 0.5 * dt * E);
  MatrixXd rhs = h * push;
  rhs.leftCols(n) += I;
  rhs.middleCols(n, n) += dt * I;
  MatrixXd lhs = I - h * G;
  if (damped) {
    rhs += h * E * W.solve(velocity);
    lhs -= 0.5 * h * dt * E * W.solve(G);
  }
  MatrixXd T(N, N);
  T.topRows(n) = lhs.partialPivLu().solve(rhs);
  velocity += 0.5 * dt * G * T.topRows(n);
  T.middleRows(n, n) = damped ? MatrixXd(W.solve(velocity)) : velocity;
  T.bottomRows(m) = next_x;
  return T;
}

/// The explicit staggered scheme: the step to t_{n+1} takes P = 2 f_n - f_{n-1},
///   (I + h K) q_{n+1} = q_n + dt q'_n + h (a_n + P),   a_{n+1} = -K q_{n+1} + P,
///   q'_{n+1} = q'_n + dt/2 (a_n + a_{n+1}),   on Y = [q; q'; a; x; f_{n-1}].
MatrixXd staggered(const LinearFlutterSystem& system, const DiscreteStateSpace& aero, const InputBlocks& b, double s) {
  const Eigen::Index n = system.size(), m = aero.states(), N = 4 * n + m;
  const double dt = aero.dt, h = 0.25 * dt * dt;
  const MatrixXd I = MatrixXd::Identity(n, n);
  const MatrixXd& K = system.stiffness();
  MatrixXd force = MatrixXd::Zero(n, N);  // f_n of Y_n
  force.block(0, 0, n, n) = s * b.Dq;
  force.block(0, n, n, n) = s * b.Dv;
  force.block(0, 3 * n, n, m) = s * aero.C;
  MatrixXd P = 2.0 * force;
  P.block(0, 3 * n + m, n, n) -= I;
  MatrixXd q = h * P;
  q.block(0, 0, n, n) += I;
  q.block(0, n, n, n) += dt * I;
  q.block(0, 2 * n, n, n) += h * I;
  MatrixXd T = MatrixXd::Zero(N, N);
  T.topRows(n) = (I + h * K).llt().solve(q);
  T.middleRows(2 * n, n) = -K * T.topRows(n) + P;
  T.middleRows(n, n) = 0.5 * dt * T.middleRows(2 * n, n);
  T.block(n, n, n, n) += I;
  T.block(n, 2 * n, n, n) += 0.5 * dt * I;
  T.block(3 * n, 0, m, n) = b.Bq;
  T.block(3 * n, n, m, n) = b.Bv;
  T.block(3 * n, 3 * n, m, m) = aero.A;
  T.bottomRows(n) = force;
  return T;
}

/// S T S^-1 with S = diag(1, dt, dt^2 ...): the rates (q' by dt; q'' and the forces by dt^2)
/// in the units of q. The eigenvalues are T's; the solver's error, eps times the norm, no
/// longer carries the stiff modes' K dt (1e6 on a strip), which ln(z) / dt amplifies by 1/dt.
MatrixXd balanced(MatrixXd T, Eigen::Index n, const DiscreteStateSpace& aero, DiscreteCoupling coupling) {
  const double dt = aero.dt;
  Eigen::VectorXd S = Eigen::VectorXd::Ones(T.rows());
  S.segment(n, n).setConstant(dt);
  if (coupling == DiscreteCoupling::staggered) {
    S.segment(2 * n, n).setConstant(dt * dt);
    S.tail(n).setConstant(dt * dt);
  }
  return S.asDiagonal() * T * S.cwiseInverse().asDiagonal();
}

/// The eigenvalue solver of T, checked.
Eigen::EigenSolver<MatrixXd> solve(const MatrixXd& T, bool vectors) {
  Eigen::EigenSolver<MatrixXd> es(T, vectors);
  if (es.info() != Eigen::Success) throw SolverError("discrete flutter system: the eigenvalue solver did not converge");
  return es;
}

}  // namespace

MatrixXd discrete_step_matrix(const LinearFlutterSystem& system, const DiscreteStateSpace& aero, double scale,
                              DiscreteCoupling coupling) {
  const InputBlocks b = input_blocks(system, aero);
  return coupling == DiscreteCoupling::simultaneous ? simultaneous(system, aero, b, scale)
                                                    : staggered(system, aero, b, scale);
}

std::vector<std::complex<double>> discrete_eigenvalues(const LinearFlutterSystem& system,
                                                       const DiscreteStateSpace& aero, double scale,
                                                       DiscreteCoupling coupling) {
  const auto es =
      solve(balanced(discrete_step_matrix(system, aero, scale, coupling), system.size(), aero, coupling), false);
  std::vector<std::complex<double>> roots;
  for (const std::complex<double>& z : es.eigenvalues())
    if (z.imag() >= 0.0 && z != 0.0) roots.push_back(std::log(z) / aero.dt);
  sort_roots(roots);
  return roots;
}

// ---- IdentifiedAerodynamics -------------------------------------------------------------------

IdentifiedAerodynamics::IdentifiedAerodynamics(DiscreteStateSpace model, const FlowCondition& identified,
                                               DiscreteCoupling coupling)
    : model_(std::move(model)), identified_(identified), coupling_(coupling) {
  if (model_.D.cols() != 2 * model_.D.rows())
    throw_input_error("identified aerodynamics: a model of {} inputs for {} forces; expected [q; q'], twice as many",
                      model_.D.cols(), model_.D.rows());
  if (!(identified_.speed > 0.0) || !(identified_.dynamic_pressure_over_beta > 0.0))
    throw_input_error("identified aerodynamics: the identification's stream has speed {} m/s and rho U^2/beta {} Pa",
                      identified_.speed, identified_.dynamic_pressure_over_beta);
}

AeroStateSpace IdentifiedAerodynamics::at(const FlowCondition&) const {
  throw_input_error(
      "identified aerodynamics: a discrete-time model at the shell step has no continuous-time form (its roots come "
      "from the one-step map, discrete_flutter.h)");
}

DiscreteStateSpace IdentifiedAerodynamics::scaled(const FlowCondition& flow, double& scale) const {
  if (!flow.damping)
    throw_input_error(
        "identified aerodynamics: the model's forces cannot be split into a stiffness and a damping part; "
        "--no-aero-damping applies to piston theory only");
  if (!(flow.mach > 1.0) || !(flow.speed >= 0.0))
    throw_input_error("identified aerodynamics: the stream at Mach {} and {} m/s is not supersonic", flow.mach,
                      flow.speed);
  // At rest (a lambda sweep's lambda = 0) the model has no forces: its step stays.
  const double r = flow.speed > 0.0 ? identified_.speed / flow.speed : 1.0;
  const Eigen::Index n = model_.D.rows();
  DiscreteStateSpace s = model_;
  s.dt = model_.dt * r;
  s.D.rightCols(n) *= r;
  s.B.rightCols(n) *= r;
  scale = flow.dynamic_pressure_over_beta / identified_.dynamic_pressure_over_beta;
  return s;
}

std::vector<std::complex<double>> IdentifiedAerodynamics::roots(const LinearFlutterSystem& system,
                                                                const FlowCondition& flow) const {
  double scale = 0.0;
  const DiscreteStateSpace s = scaled(flow, scale);
  return discrete_eigenvalues(system, s, scale, coupling_);
}

std::pair<std::complex<double>, Eigen::VectorXcd> IdentifiedAerodynamics::least_stable_mode(
    const LinearFlutterSystem& system, const FlowCondition& flow) const {
  double scale = 0.0;
  const DiscreteStateSpace s = scaled(flow, scale);
  const auto es = solve(discrete_step_matrix(system, s, scale, coupling_), true);
  Eigen::Index best = -1;
  for (Eigen::Index k = 0; k < es.eigenvalues().size(); ++k) {
    const auto z = es.eigenvalues()(k);
    if (z.imag() >= 0.0 && z != 0.0 && (best < 0 || std::abs(z) > std::abs(es.eigenvalues()(best)))) best = k;
  }
  if (best < 0) throw SolverError("discrete flutter system: no root");
  return {std::log(es.eigenvalues()(best)) / s.dt, system.shape(es.eigenvectors().col(best).head(system.size()))};
}

std::unique_ptr<ModalAerodynamics> IdentifiedAerodynamics::truncated(int k) const {
  const Eigen::Index n = model_.D.rows();
  if (k < 1 || k > n)
    throw SolverError(fmt::format("identified aerodynamics: cannot truncate a model of {} coordinates to {}", n, k));
  // Keep the forces and inputs of the first k coordinates; the states of the others' inputs
  // are then never driven (their z = 0 roots are dropped).
  DiscreteStateSpace t = model_;
  t.C = model_.C.topRows(k);
  t.D.resize(k, 2 * k);
  t.D << model_.D.block(0, 0, k, k), model_.D.block(0, n, k, k);
  t.B.resize(model_.B.rows(), 2 * k);
  t.B << model_.B.leftCols(k), model_.B.middleCols(n, k);
  return std::make_unique<IdentifiedAerodynamics>(std::move(t), identified_, coupling_);
}

}  // namespace shellflow::coupling
