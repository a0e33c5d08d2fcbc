#pragma once
// Point queries on a shell state for coupling and probes (shell.md §12): mid-surface
// position, interpolated nodal vectors (displacement, velocity, acceleration) and the
// current unit normal at a stored (element, xi1, xi2) point; cubic Hermite interpolation of
// nodal motion inside a time step.
#include "shellflow/shell/shell_model.h"

namespace shellflow::shell {

/// A point of the mid-surface in parametric form.
struct ShellPoint {
  Index element = 0;
  Vec2 xi = Vec2::Zero();
};

/// Sum_j phi_j(xi) v_j of the 3-vector at offset `component` (0: x rows, 3: G rows) of a
/// 7-per-node vector (u: displacement, v: velocity, a: acceleration).
Vec3 interpolate_nodal(const ShellModel& model, const ShellPoint& p, const Eigen::VectorXd& nodal, int component = 0);
/// Current mid-surface point x̂ = X̂ + Σ phi_j Δx_j.
Vec3 mid_surface_position(const ShellModel& model, const ShellPoint& p, const Eigen::VectorXd& u);
/// Current unit normal x̂_1 × x̂_2 / |...| (oriented like the directors V).
Vec3 mid_surface_normal(const ShellModel& model, const ShellPoint& p, const Eigen::VectorXd& u);

/// Cubic Hermite interpolation of a nodal quantity over [t_i, t_i + dt], tau in [0, 1]
/// (shell.md §12): reproduces x and v at both ends.
Vec3 hermite_position(const Vec3& x0, const Vec3& v0, const Vec3& x1, const Vec3& v1, double dt, double tau);
/// Its time derivative.
Vec3 hermite_velocity(const Vec3& x0, const Vec3& v0, const Vec3& x1, const Vec3& v1, double dt, double tau);

}  // namespace shellflow::shell
