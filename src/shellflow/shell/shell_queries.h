#pragma once
// Point queries on a shell state for coupling and probes (shell.md §12): mid-surface
// position, interpolated nodal vectors (displacement, velocity, acceleration) and the
// current unit normal at a stored (element, xi1, xi2) point; cubic Hermite interpolation of
// nodal motion inside a time step.
#include <vector>

#include "shellflow/mesh/spatial_index.h"
#include "shellflow/shell/shell_model.h"
#include "shellflow/shell/shell_point.h"

namespace shellflow::shell {

/// Sum_j phi_j(xi) v_j of the 3-vector at offset `component` (0: x rows, 3: G rows) of a
/// 7-per-node vector (u: displacement, v: velocity, a: acceleration).
Vec3 interpolate_nodal(const ShellModel& model, const ShellPoint& p, const Eigen::VectorXd& nodal, int component = 0);
/// Current mid-surface point x̂ = X̂ + Σ phi_j Δx_j.
Vec3 mid_surface_position(const ShellModel& model, const ShellPoint& p, const Eigen::VectorXd& u);
/// Current unit normal x̂_1 × x̂_2 / |...| (oriented like the directors V).
Vec3 mid_surface_normal(const ShellModel& model, const ShellPoint& p, const Eigen::VectorXd& u);

/// Result of a closest-point query on the mid-surface.
struct ClosestPoint {
  ShellPoint point;              ///< (element, ξ1, ξ2) of the closest mid-surface point
  Vec3 position = Vec3::Zero();  ///< that point x̂(ξ)
  double distance = 0.0;         ///< |p − x̂|
  double offset = 0.0;           ///< (p − x̂)·n, n the unit normal there (oriented like V)
};

/// Closest-point location on the curved mid-surface (shell.md §12) of the undeformed shell
/// or of a state u: candidates from an AABB tree of the element boxes (padded: cubic
/// elements bulge past their nodes), then Newton on ξ minimising |x̂(ξ) − p|² in each
/// candidate, started from the closest point of the vertex triangle; when the minimiser
/// leaves the triangle, 1-D Newton on its three edges. The model must outlive the locator.
class ShellLocator {
 public:
  explicit ShellLocator(const ShellModel& model);
  ShellLocator(const ShellModel& model, const Eigen::VectorXd& u);

  ClosestPoint closest(const Vec3& p) const;
  /// The closest point of one element's mid-surface patch.
  ClosestPoint closest_on_element(Index element, const Vec3& p) const;

 private:
  const ShellModel& model_;
  std::vector<Vec3> positions_;  ///< current nodal positions
  mesh::BoxTree tree_;
};

/// Cubic Hermite interpolation of a nodal quantity over [t_i, t_i + dt], tau in [0, 1]
/// (shell.md §12): reproduces x and v at both ends.
Vec3 hermite_position(const Vec3& x0, const Vec3& v0, const Vec3& x1, const Vec3& v1, double dt, double tau);
/// Its time derivative.
Vec3 hermite_velocity(const Vec3& x0, const Vec3& v0, const Vec3& x1, const Vec3& v1, double dt, double tau);

}  // namespace shellflow::shell
