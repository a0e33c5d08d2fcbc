#pragma once
// The shell's motion inside one shell step, as the mesh movers and the fluid wall see it
// (coupling.md, time stepping, step 2): cubic Hermite interpolation in time of the shell's
// positions from x, v at both ends of the step [t0, t0 + dt]. Points are given by their
// initial positions and located once on the shell mid-surface (closest point); their
// displacement and velocity are then sums over the element's nodes with precomputed shape
// values, so an evaluation costs N multiply-adds per point (N = 10 for cubic triangles).
#include <Eigen/Core>
#include <span>
#include <vector>

#include "shellflow/motion/boundary_motion.h"
#include "shellflow/shell/shell_model.h"
#include "shellflow/shell/shell_queries.h"

namespace shellflow::coupling {

class ShellStepMotion final : public motion::BoundaryMotion {
 public:
  /// Points farther than `max_gap` from the mid-surface are refused (InputError).
  ShellStepMotion(const shell::ShellModel& model, double max_gap);

  /// The window of one shell step: displacement u and velocity v (7 per node; the position
  /// rows are used) at t0 and at t0 + dt. Before the first call the shell is at rest.
  void set_window(double t0, double dt, const Eigen::VectorXd& u0, const Eigen::VectorXd& v0, const Eigen::VectorXd& u1,
                  const Eigen::VectorXd& v1);
  /// A window of zero length: the shell stands at state (u, v) (at rest if v = 0).
  void set_state(double t, const Eigen::VectorXd& u, const Eigen::VectorXd& v);

  int register_points(std::span<const Vec3> initial_positions) override;
  /// Registers points given directly as shell points (e.g. the interface map's).
  int register_shell_points(std::span<const shell::ShellPoint> points);
  /// Displacement (Hermite) and velocity (its time derivative) at t; t is clamped to the window.
  void evaluate(int handle, double time, std::span<Vec3> displacement, std::span<Vec3> velocity) const override;

  /// The Hermite window as 4 time modes: the interpolated x0, v0, x1, v1 of the points, with
  /// coefficients h00, dt h10, h01, dt h11 (and their time derivatives); a window of zero
  /// length: (1, 0, 0, 0) and (0, 1, 0, 0).
  int num_time_modes() const override { return 4; }
  std::uint64_t window_id() const override { return window_id_; }
  void evaluate_time_mode(int handle, int k, std::span<Vec3> field) const override;
  void time_coefficients(double time, std::span<double> c, std::span<double> dc) const override;

 private:
  struct PointSet {
    std::vector<Index> nodes;  ///< N per point
    std::vector<double> phi;   ///< N per point
  };
  const shell::ShellModel& model_;
  double max_gap_;
  int nodes_per_element_;
  std::vector<PointSet> sets_;
  /// The nodal field of time mode k.
  const std::vector<Vec3>& mode_field(int k) const;
  double t0_ = 0.0, dt_ = 0.0;
  std::uint64_t window_id_ = 0;
  // Nodal mid-surface displacement and velocity at both ends of the window.
  std::vector<Vec3> x0_, v0_, x1_, v1_;
};

}  // namespace shellflow::coupling
