#include "shellflow/coupling/piston_theory.h"

#include <cmath>
#include <numbers>

#include "shellflow/core/error.h"

namespace shellflow::coupling {

PistonTheory::PistonTheory(const shell::ShellModel& model, PistonTheoryFlow flow)
    : model_(model), flow_(flow), basis_(model) {
  if (!(flow_.mach > 1.0) || !std::isfinite(flow_.mach))
    throw_input_error(
        "piston theory needs a supersonic free stream, got Mach {}; use "
        "fluid.model: euler below Mach 1",
        flow_.mach);
  if (flow_.mach < kPistonTheoryMinMach)  // io::check_coupled_case says it first, with the case's key
    throw_input_error("piston theory at Mach {}: below its validity limit, Mach {}; use fluid.model: euler", flow_.mach,
                      kPistonTheoryMinMach);
  if (!(flow_.density > 0.0) || !(flow_.speed > 0.0))
    throw_input_error("piston theory: free-stream density {} kg/m^3 and speed {} m/s must be positive", flow_.density,
                      flow_.speed);
  flow_.direction.normalize();
  flow_.wet_normal.normalize();
  const double m2 = flow_.mach * flow_.mach;
  const double beta = std::sqrt(m2 - 1.0);
  q_stiffness_ = flow_.density * flow_.speed * flow_.speed / beta;
  q_damping_ = flow_.density * flow_.speed * (m2 - 2.0) / ((m2 - 1.0) * beta);

  const auto n = static_cast<std::size_t>(basis_.n);
  const auto& points = model.load_points();
  dphi_dx_.resize(n * points.size());
  normal_.resize(points.size());
  sign_.resize(points.size());
  for (std::size_t k = 0; k < points.size(); ++k) {
    const auto& lp = points[k];
    const double* dN = basis_.dphi.data() + 2 * n * k;
    Vec3 X1, X2;
    basis_.tangents(model, k, nullptr, X1, X2);
    // Surface gradient: grad phi = g^{ab} phi_,a X_b; its component along the flow.
    Eigen::Matrix2d g;
    g << X1.dot(X1), X1.dot(X2), X1.dot(X2), X2.dot(X2);
    const Eigen::Matrix2d gi = g.inverse();
    const Eigen::Vector2d e(X1.dot(flow_.direction), X2.dot(flow_.direction));
    const Eigen::Vector2d c = gi * e;  // d/dx = c1 d/dxi1 + c2 d/dxi2
    for (std::size_t a = 0; a < n; ++a) dphi_dx_[n * k + a] = c.x() * dN[2 * a] + c.y() * dN[2 * a + 1];
    sign_[k] = lp.normal.dot(flow_.wet_normal) >= 0.0 ? 1.0 : -1.0;
    normal_[k] = sign_[k] * lp.normal;
  }
  check_geometry(points);
}

void PistonTheory::check_geometry(std::span<const shell::LoadPoint> points) const {
  // The wet side: the wet normal crosses the panel (within 60 degrees of every normal).
  Vec3 mean = Vec3::Zero();
  for (std::size_t k = 0; k < points.size(); ++k) {
    const double c = std::abs(points[k].normal.dot(flow_.wet_normal));
    if (c < 0.5)
      throw_input_error(
          "coupling.wet_normal [{:.6g}, {:.6g}, {:.6g}] lies {:.1f} degrees from the panel's normal at ({:.6g}, "
          "{:.6g}, {:.6g}), close to the panel's plane: it must point from the shell into the flow, across the "
          "panel (within 60 degrees of its normal)",
          flow_.wet_normal.x(), flow_.wet_normal.y(), flow_.wet_normal.z(), std::acos(c) * 180.0 / std::numbers::pi,
          points[k].position.x(), points[k].position.y(), points[k].position.z());
    mean += points[k].weight * normal_[k];
  }
  // The stream along the panel: piston theory's pressure is that of small slopes of a panel
  // the stream passes along, not of a stream blowing onto it.
  if (mean.norm() > 0.0) {
    const double s = flow_.direction.dot(mean.normalized());
    if (std::abs(s) > kPistonTheoryMaxIncidence)
      throw_input_error(
          "fluid.free_stream.direction [{:.6g}, {:.6g}, {:.6g}] is {:.2f} degrees {} the panel (mean wet normal "
          "[{:.4g}, {:.4g}, {:.4g}]); piston theory models a stream along the panel (at most {:.2f} degrees): turn "
          "the direction into the panel's plane, or use fluid.model: euler",
          flow_.direction.x(), flow_.direction.y(), flow_.direction.z(),
          std::asin(std::abs(s)) * 180.0 / std::numbers::pi, s < 0.0 ? "into" : "away from", mean.normalized().x(),
          mean.normalized().y(), mean.normalized().z(),
          std::asin(kPistonTheoryMaxIncidence) * 180.0 / std::numbers::pi);
  }
}

void PistonTheory::pressure_rise(const Eigen::VectorXd& u, const Eigen::VectorXd& v, std::span<double> dp) const {
  const auto n = static_cast<std::size_t>(basis_.n);
  for (std::size_t k = 0; k < normal_.size(); ++k) {
    Vec3 du_dx = Vec3::Zero(), vel = Vec3::Zero();
    for (std::size_t a = 0; a < n; ++a) {
      const Eigen::Index row = shell::dofs_per_node * basis_.nodes[n * k + a];
      du_dx += dphi_dx_[n * k + a] * u.segment<3>(row);
      vel += basis_.phi[n * k + a] * v.segment<3>(row);
    }
    dp[k] = q_stiffness_ * normal_[k].dot(du_dx) + q_damping_ * normal_[k].dot(vel);
  }
}

void PistonTheory::matrices(shell::SparseMatrix& A, shell::SparseMatrix& D) const {
  matrices(A, D, q_stiffness_, q_damping_);
}

void PistonTheory::matrices(shell::SparseMatrix& A, shell::SparseMatrix& D, double q_stiffness,
                            double q_damping) const {
  A = model_.make_matrix();
  D = model_.make_matrix();
  A.coeffs().setZero();
  D.coeffs().setZero();
  const auto n = static_cast<std::size_t>(basis_.n);
  const auto& points = model_.load_points();
  for (std::size_t k = 0; k < points.size(); ++k) {
    const Vec3& N = points[k].normal;
    const Mat3 NN = N * N.transpose();
    const double w = points[k].weight;
    for (std::size_t j = 0; j < n; ++j) {
      const Eigen::Index rj = shell::dofs_per_node * basis_.nodes[n * k + j];
      for (std::size_t l = 0; l < n; ++l) {
        const Eigen::Index cl = shell::dofs_per_node * basis_.nodes[n * k + l];
        const double a = q_stiffness * w * basis_.phi[n * k + j] * dphi_dx_[n * k + l];
        const double d = q_damping * w * basis_.phi[n * k + j] * basis_.phi[n * k + l];
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) {
            if (NN(r, c) == 0.0) continue;
            A.coeffRef(rj + r, cl + c) += a * NN(r, c);
            D.coeffRef(rj + r, cl + c) += d * NN(r, c);
          }
      }
    }
  }
}

}  // namespace shellflow::coupling
