#include "shellflow/coupling/forced_motion.h"

#include <fmt/format.h>

#include <cmath>
#include <numbers>

#include "shellflow/core/error.h"
#include "shellflow/coupling/load_point_basis.h"

namespace shellflow::coupling {

namespace {
constexpr double pi = std::numbers::pi;
}

double ModalPulses::shape(int p, double t) const {
  const double s = (t - start(p)) / width;
  return s <= 0.0 || s >= 1.0 ? 0.0 : 0.5 * (1.0 - std::cos(2.0 * pi * s));
}

double ModalPulses::q(int j, double t) const { return peak[std::size_t(j)] * shape(j, t); }

double ModalPulses::dq(int j, double t) const {
  const double s = (t - start(j)) / width;
  const double rate = s <= 0.0 || s >= 1.0 ? 0.0 : std::sin(2.0 * pi * s);
  return peak[std::size_t(j)] * pi / width * (rate + shape(int(peak.size()) + j, t));
}

Eigen::MatrixXd ForcedMotionRecord::input_matrix() const {
  Eigen::MatrixXd m(Eigen::Index(inputs.size()), inputs.empty() ? 0 : inputs.front().size());
  for (std::size_t n = 0; n < inputs.size(); ++n) m.row(Eigen::Index(n)) = inputs[n].transpose();
  return m;
}

Eigen::MatrixXd ForcedMotionRecord::force_matrix() const {
  Eigen::MatrixXd m(Eigen::Index(forces.size()), forces.empty() ? 0 : forces.front().size());
  for (std::size_t n = 0; n < forces.size(); ++n) m.row(Eigen::Index(n)) = forces[n].transpose();
  return m;
}

ForcedModalMotion::ForcedModalMotion(const shell::ShellModel& model, const Eigen::MatrixXd& modes, double width,
                                     double gap, double amplitude, double dt, AerodynamicModel& flow,
                                     ShellStepMotion& motion)
    : modes_(modes), dt_(dt), flow_(flow), motion_(motion) {
  if (!(width > 0.0) || !(gap >= 0.0) || !(amplitude > 0.0) || !(dt > 0.0) || modes.cols() < 1)
    throw Error(fmt::format("forced motion: pulse width {} s, gap {} s, amplitude {} m, step {} s, {} modes", width,
                            gap, amplitude, dt, modes.cols()));
  if (modes.rows() != model.num_dofs())
    throw Error(fmt::format("forced motion: modes of {} dofs for a shell of {}", modes.rows(), model.num_dofs()));
  pulses_.width = width;
  pulses_.gap = gap;
  // Each mode's peak mid-surface deflection: the largest nodal displacement of the mode.
  for (Eigen::Index j = 0; j < modes.cols(); ++j) {
    double largest = 0.0;
    for (Index n = 0; n < model.num_nodes(); ++n)
      largest = std::max(largest, modes.col(j).segment<3>(shell::dofs_per_node * n).norm());
    if (!(largest > 0.0)) throw Error(fmt::format("forced motion: mode {} does not move the mid-surface", j + 1));
    pulses_.peak.push_back(amplitude / largest);
  }
  // The load matrix: f_i = sum_k phi_i(x_k) . (-sign_k dp_k) w_k X_1 x X_2.
  const LoadPointBasis basis(model);
  const auto nn = std::size_t(basis.n);
  load_ = Eigen::MatrixXd::Zero(modes.cols(), Eigen::Index(basis.size()));
  Vec3 X1, X2;
  for (std::size_t k = 0; k < basis.size(); ++k) {
    basis.tangents(model, k, nullptr, X1, X2);
    const Vec3 area = basis.plane_weight[k] * X1.cross(X2);
    for (std::size_t a = 0; a < nn; ++a) {
      const Eigen::Index row = shell::dofs_per_node * basis.nodes[nn * k + a];
      load_.col(Eigen::Index(k)) += basis.phi[nn * k + a] * (modes.middleRows<3>(row).transpose() * area);
    }
  }
  const auto sign = flow.sign();
  if (sign.size() != basis.size())
    throw Error(fmt::format("forced motion: the aerodynamic model has {} load points, the shell {}", sign.size(),
                            basis.size()));
  for (std::size_t k = 0; k < basis.size(); ++k) load_.col(Eigen::Index(k)) *= -sign[k];
  dp_.assign(basis.size(), 0.0);
  record_.dt = dt;
  Eigen::VectorXd u, v;
  shell_state(0.0, u, v);
  motion_.set_state(0.0, u, v);
  sample_at(0.0);
}

long ForcedModalMotion::total_steps() const { return std::lround(std::ceil(pulses_.end() / dt_ - 1e-9)); }

Eigen::VectorXd ForcedModalMotion::modal_state(double t) const {
  const Eigen::Index K = modes_.cols();
  Eigen::VectorXd state(2 * K);
  for (Eigen::Index j = 0; j < K; ++j) {
    state(j) = pulses_.q(int(j), t);
    state(K + j) = pulses_.dq(int(j), t);
  }
  return state;
}

void ForcedModalMotion::shell_state(double t, Eigen::VectorXd& u, Eigen::VectorXd& v) const {
  const Eigen::VectorXd state = modal_state(t);
  u = modes_ * state.head(modes_.cols());
  v = modes_ * state.tail(modes_.cols());
}

Eigen::VectorXd ForcedModalMotion::modal_forces(std::span<const double> dp) const {
  return load_ * Eigen::Map<const Eigen::VectorXd>(dp.data(), Eigen::Index(dp.size()));
}

void ForcedModalMotion::sample_at(double t) {
  const Eigen::VectorXd state = modal_state(t);
  const Eigen::Index K = modes_.cols();
  flow_.pressure_rise(modes_ * state.head(K), modes_ * state.tail(K), dp_);
  record_.time.push_back(t);
  record_.inputs.push_back(state);
  record_.forces.push_back(modal_forces(dp_));
}

FlowStepReport ForcedModalMotion::step() {
  // The step's times as the shell's clock counts them: t_n = n dt (no accumulated sums).
  const long n = steps();
  const double t0 = double(n) * dt_, t1 = double(n + 1) * dt_;
  Eigen::VectorXd u0, v0, u1, v1;
  shell_state(t0, u0, v0);
  shell_state(t1, u1, v1);
  motion_.set_window(t0, t1 - t0, u0, v0, u1, v1);
  const FlowStepReport report = flow_.advance(motion_, t1);
  sample_at(t1);
  return report;
}

void ForcedModalMotion::save(ArchiveWriter& out) const {
  flow_.save(out);
  out.put(std::int64_t(steps()));
  for (std::size_t n = 0; n < record_.time.size(); ++n) {
    out.put(record_.inputs[n]);
    out.put(record_.forces[n]);
  }
}

void ForcedModalMotion::restore(ArchiveReader& in) {
  flow_.restore(in);
  const auto steps = in.get<std::int64_t>();
  if (steps < 0 || steps > total_steps())
    throw InputError(fmt::format("the checkpoint's forced motion has {} steps; this run has {}", steps, total_steps()));
  const Eigen::Index K = modes_.cols();
  ForcedMotionRecord r;
  r.dt = dt_;
  for (std::int64_t n = 0; n <= steps; ++n) {
    const std::vector<double> input = in.get_vector<double>(), force = in.get_vector<double>();
    in.expect_size("the forced motion's inputs", input.size(), std::size_t(2 * K));
    in.expect_size("the forced motion's forces", force.size(), std::size_t(K));
    r.time.push_back(double(n) * dt_);
    r.inputs.push_back(Eigen::Map<const Eigen::VectorXd>(input.data(), 2 * K));
    r.forces.push_back(Eigen::Map<const Eigen::VectorXd>(force.data(), K));
  }
  record_ = std::move(r);
  Eigen::VectorXd u, v;
  shell_state(time(), u, v);
  motion_.set_state(time(), u, v);
}

}  // namespace shellflow::coupling
