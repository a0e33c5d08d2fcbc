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

// ---- DiscreteAerodynamics ---------------------------------------------------------------------

AeroStateSpace DiscreteAerodynamics::at(const FlowCondition&) const {
  throw_input_error(
      "identified aerodynamics: a discrete-time model at the shell step has no continuous-time form (its roots come "
      "from the one-step map, discrete_flutter.h)");
}

std::vector<std::complex<double>> DiscreteAerodynamics::roots(const LinearFlutterSystem& system,
                                                              const FlowCondition& flow) const {
  double scale = 0.0;
  const DiscreteStateSpace s = scaled(flow, scale);
  return discrete_eigenvalues(system, s, scale, coupling_);
}

std::pair<std::complex<double>, Eigen::VectorXcd> DiscreteAerodynamics::least_stable_mode(
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

namespace {

/// The flows a model can be scaled to: with its damping, supersonic.
void check_flow(const FlowCondition& flow) {
  if (!flow.damping)
    throw_input_error(
        "identified aerodynamics: the model's forces cannot be split into a stiffness and a damping part; "
        "--no-aero-damping applies to piston theory only");
  if (!(flow.mach > 1.0) || !(flow.speed >= 0.0))
    throw_input_error("identified aerodynamics: the stream at Mach {} and {} m/s is not supersonic", flow.mach,
                      flow.speed);
}

void check_identified(const FlowCondition& identified) {
  if (!(identified.speed > 0.0) || !(identified.dynamic_pressure_over_beta > 0.0) || !(identified.mach > 1.0))
    throw_input_error(
        "identified aerodynamics: the identification's stream has Mach {}, speed {} m/s and rho U^2/beta {} Pa",
        identified.mach, identified.speed, identified.dynamic_pressure_over_beta);
}

}  // namespace

// ---- IdentifiedAerodynamics -------------------------------------------------------------------

IdentifiedAerodynamics::IdentifiedAerodynamics(DiscreteStateSpace model, const FlowCondition& identified,
                                               DiscreteCoupling coupling)
    : DiscreteAerodynamics(coupling), model_(std::move(model)), identified_(identified) {
  if (model_.D.cols() != 2 * model_.D.rows())
    throw_input_error("identified aerodynamics: a model of {} inputs for {} forces; expected [q; q'], twice as many",
                      model_.D.cols(), model_.D.rows());
  check_identified(identified_);
}

DiscreteStateSpace IdentifiedAerodynamics::scaled(const FlowCondition& flow, double& scale) const {
  check_flow(flow);
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

// ---- MachInterpolatedAerodynamics -------------------------------------------------------------

FirModel truncated_fir(const FirModel& model, int k) {
  const Eigen::Index n = model.outputs();
  if (k < 1 || k > n || model.inputs() != 2 * n)
    throw SolverError(fmt::format("identified aerodynamics: cannot truncate a model of {} coordinates to {}", n, k));
  FirModel t;
  t.dt = model.dt;
  for (const MatrixXd& H : model.taps) {
    t.taps.emplace_back(k, 2 * k);
    t.taps.back() << H.block(0, 0, k, k), H.block(0, n, k, k);
  }
  return t;
}

MachInterpolatedAerodynamics::MachInterpolatedAerodynamics(FirModel low, const FlowCondition& at_low, FirModel high,
                                                           const FlowCondition& at_high, DiscreteCoupling coupling)
    : DiscreteAerodynamics(coupling),
      models_{std::move(low), std::move(high)},
      flows_{at_low, at_high},
      ends_{IdentifiedAerodynamics(models_[0].state_space(), at_low, coupling),
            IdentifiedAerodynamics(models_[1].state_space(), at_high, coupling)} {
  if (!(flows_[0].mach < flows_[1].mach))
    throw_input_error("identified aerodynamics: the identifications' Mach numbers {} and {} are not increasing",
                      flows_[0].mach, flows_[1].mach);
  const double c0 = flows_[0].speed / flows_[0].mach, c1 = flows_[1].speed / flows_[1].mach;
  if (std::abs(c0 - c1) > 1e-9 * c0 || std::abs(flows_[0].density - flows_[1].density) > 1e-9 * flows_[0].density)
    throw_input_error(
        "identified aerodynamics: the identifications at Mach {} and {} have other streams (sound speeds {} and {} "
        "m/s, densities {} and {} kg/m^3); interpolate in Mach at one density and pressure",
        flows_[0].mach, flows_[1].mach, c0, c1, flows_[0].density, flows_[1].density);
  if (models_[0].dt != models_[1].dt || models_[0].outputs() != models_[1].outputs())
    throw_input_error(
        "identified aerodynamics: the identifications at Mach {} and {} have other steps ({} and {} s) or modes ({} "
        "and {})",
        flows_[0].mach, flows_[1].mach, models_[0].dt, models_[1].dt, models_[0].outputs(), models_[1].outputs());
}

DiscreteStateSpace MachInterpolatedAerodynamics::scaled(const FlowCondition& flow, double& scale) const {
  check_flow(flow);
  if (flow.mach <= flows_[0].mach) return ends_[0].scaled(flow, scale);
  if (flow.mach >= flows_[1].mach) return ends_[1].scaled(flow, scale);
  const double w1 = (flows_[1].mach - flow.mach) / (flows_[1].mach - flows_[0].mach);
  const double c_id = flows_[0].speed / flows_[0].mach, c = flow.speed / flow.mach;
  const Eigen::Index n = models_[0].outputs();
  FirModel blend;
  blend.dt = models_[0].dt * (flow.speed > 0.0 ? c_id / c : 1.0);
  blend.taps.assign(std::max(models_[0].taps.size(), models_[1].taps.size()), MatrixXd::Zero(n, 2 * n));
  for (int i = 0; i < 2; ++i) {
    const double w = i == 0 ? w1 : 1.0 - w1;
    const double s = w * flow.dynamic_pressure_over_beta / flows_[i].dynamic_pressure_over_beta;
    const double v = flow.speed > 0.0 ? flows_[i].speed / flow.speed : 1.0;
    for (std::size_t j = 0; j < models_[i].taps.size(); ++j) {
      blend.taps[j].leftCols(n) += s * models_[i].taps[j].leftCols(n);
      blend.taps[j].rightCols(n) += (s * v) * models_[i].taps[j].rightCols(n);
    }
  }
  scale = 1.0;
  return blend.state_space();
}

std::unique_ptr<ModalAerodynamics> MachInterpolatedAerodynamics::truncated(int k) const {
  return std::make_unique<MachInterpolatedAerodynamics>(truncated_fir(models_[0], k), flows_[0],
                                                        truncated_fir(models_[1], k), flows_[1], coupling_);
}

}  // namespace shellflow::coupling
