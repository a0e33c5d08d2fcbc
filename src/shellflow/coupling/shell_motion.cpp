#include "shellflow/coupling/shell_motion.h"

#include <fmt/format.h>

#include <algorithm>

#include "shellflow/core/error.h"
#include "shellflow/fem/reference_element.h"

namespace shellflow::coupling {
namespace {

void nodal_positions(const Eigen::VectorXd& u, std::vector<Vec3>& out) {
  const auto n = static_cast<std::size_t>(u.size() / shell::dofs_per_node);
  out.resize(n);
  for (std::size_t j = 0; j < n; ++j) out[j] = u.segment<3>(shell::dofs_per_node * Eigen::Index(j));
}

}  // namespace

ShellStepMotion::ShellStepMotion(const shell::ShellModel& model, double max_gap)
    : model_(model), max_gap_(max_gap), nodes_per_element_(model.mesh().cells.nodes_per_element()) {
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.num_dofs());
  set_state(0.0, zero, zero);
}

void ShellStepMotion::set_window(double t0, double dt, const Eigen::VectorXd& u0, const Eigen::VectorXd& v0,
                                 const Eigen::VectorXd& u1, const Eigen::VectorXd& v1) {
  t0_ = t0;
  dt_ = dt;
  ++window_id_;
  nodal_positions(u0, x0_);
  nodal_positions(v0, v0_);
  nodal_positions(u1, x1_);
  nodal_positions(v1, v1_);
}

void ShellStepMotion::set_state(double t, const Eigen::VectorXd& u, const Eigen::VectorXd& v) {
  set_window(t, 0.0, u, v, u, v);
}

int ShellStepMotion::register_points(std::span<const Vec3> initial_positions) {
  const shell::ShellLocator locator(model_);
  std::vector<shell::ShellPoint> points(initial_positions.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const shell::ClosestPoint c = locator.closest(initial_positions[i]);
    if (c.distance > max_gap_) {
      const Vec3& p = initial_positions[i];
      throw_input_error(
          "coupling: a point of the moving boundary at ({:.6g}, {:.6g}, {:.6g}) lies "
          "{:.3e} m from the shell mid-surface, above coupling.max_gap = {:.3e} m; "
          "the space mesh's / fluid mesh's interface groups must lie on the shell",
          p.x(), p.y(), p.z(), c.distance, max_gap_);
    }
    points[i] = c.point;
  }
  return register_shell_points(points);
}

int ShellStepMotion::register_shell_points(std::span<const shell::ShellPoint> points) {
  const mesh::Mesh& m = model_.mesh();
  const fem::ReferenceElement& ref = fem::reference_element(static_cast<int>(m.cells.type));
  const auto n = static_cast<std::size_t>(nodes_per_element_);
  PointSet set;
  set.nodes.resize(n * points.size());
  set.phi.resize(n * points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double xi[2] = {points[i].xi.x(), points[i].xi.y()};
    ref.eval(xi, set.phi.data() + n * i);
    const auto conn = m.cells.element(points[i].element);
    std::copy(conn.begin(), conn.end(), set.nodes.begin() + std::ptrdiff_t(n * i));
  }
  sets_.push_back(std::move(set));
  return static_cast<int>(sets_.size()) - 1;
}

void ShellStepMotion::time_coefficients(double time, std::span<double> c, std::span<double> dc) const {
  if (c.size() < 4 || dc.size() < 4)
    throw Error(fmt::format("ShellStepMotion::time_coefficients: spans of {} and {} for 4 modes", c.size(), dc.size()));
  if (dt_ == 0.0) {  // at rest in state (x0, v0)
    c[0] = 1.0, c[1] = 0.0, c[2] = 0.0, c[3] = 0.0;
    dc[0] = 0.0, dc[1] = 1.0, dc[2] = 0.0, dc[3] = 0.0;
    return;
  }
  // Hermite basis on tau in [0, 1]: x(tau) = h00 x0 + h10 dt v0 + h01 x1 + h11 dt v1.
  const double tau = std::clamp((time - t0_) / dt_, 0.0, 1.0);
  const double t2 = tau * tau, t3 = t2 * tau;
  c[0] = 2 * t3 - 3 * t2 + 1;
  c[1] = (t3 - 2 * t2 + tau) * dt_;
  c[2] = -2 * t3 + 3 * t2;
  c[3] = (t3 - t2) * dt_;
  // d/dt = (1/dt) d/dtau.
  dc[0] = (6 * t2 - 6 * tau) / dt_;
  dc[1] = 3 * t2 - 4 * tau + 1;
  dc[2] = -dc[0];
  dc[3] = 3 * t2 - 2 * tau;
}

const std::vector<Vec3>& ShellStepMotion::mode_field(int k) const {
  switch (k) {
    case 0:
      return x0_;
    case 1:
      return v0_;
    case 2:
      return x1_;
    case 3:
      return v1_;
  }
  throw Error(fmt::format("ShellStepMotion: no time mode {} (4 modes)", k));
}

void ShellStepMotion::evaluate_time_mode(int handle, int k, std::span<Vec3> field) const {
  const PointSet& set = sets_.at(static_cast<std::size_t>(handle));
  const auto n = static_cast<std::size_t>(nodes_per_element_);
  const std::size_t count = set.nodes.size() / n;
  if (field.size() != count)
    throw Error(fmt::format("ShellStepMotion::evaluate_time_mode: {} points, output span of {}", count, field.size()));
  const std::vector<Vec3>& nodal = mode_field(k);
  for (std::size_t i = 0; i < count; ++i) {
    Vec3 f = Vec3::Zero();
    for (std::size_t a = 0; a < n; ++a) f += set.phi[n * i + a] * nodal[static_cast<std::size_t>(set.nodes[n * i + a])];
    field[i] = f;
  }
}

void ShellStepMotion::evaluate(int handle, double time, std::span<Vec3> displacement, std::span<Vec3> velocity) const {
  const PointSet& set = sets_.at(static_cast<std::size_t>(handle));
  const auto n = static_cast<std::size_t>(nodes_per_element_);
  const std::size_t count = set.nodes.size() / n;
  if (displacement.size() != count || velocity.size() != count)
    throw Error(fmt::format("ShellStepMotion::evaluate: {} points, output spans of {} and {}", count,
                            displacement.size(), velocity.size()));
  double c[4], dc[4];
  time_coefficients(time, c, dc);
  for (std::size_t i = 0; i < count; ++i) {
    Vec3 x0 = Vec3::Zero(), v0 = Vec3::Zero(), x1 = Vec3::Zero(), v1 = Vec3::Zero();
    for (std::size_t a = 0; a < n; ++a) {
      const double w = set.phi[n * i + a];
      const auto j = static_cast<std::size_t>(set.nodes[n * i + a]);
      x0 += w * x0_[j];
      v0 += w * v0_[j];
      x1 += w * x1_[j];
      v1 += w * v1_[j];
    }
    // A window of zero length has c = (1, 0, 0, 0), dc = (0, 1, 0, 0): x0 and v0 exactly.
    displacement[i] = c[0] * x0 + c[1] * v0 + c[2] * x1 + c[3] * v1;
    velocity[i] = dc[0] * x0 + dc[1] * v0 + dc[2] * x1 + dc[3] * v1;
  }
}

}  // namespace shellflow::coupling
