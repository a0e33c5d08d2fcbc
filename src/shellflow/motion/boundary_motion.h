#pragma once
// The motion of the moving (interface) boundary, as the mesh movers see it: displacement
// and velocity at points given by their initial positions. Prescribed analytic motions
// implement it here; the coupling module implements it with the shell.
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "shellflow/core/time_function.h"
#include "shellflow/core/types.h"

namespace shellflow::motion {

class BoundaryMotion {
 public:
  virtual ~BoundaryMotion() = default;
  /// Registers points (initial positions) whose motion will be asked for, once, so that an
  /// implementation can precompute (e.g. closest shell points). Returns a handle.
  virtual int register_points(std::span<const Vec3> initial_positions) = 0;
  /// Displacement and velocity at time t of the points registered under `handle`.
  virtual void evaluate(int handle, double time, std::span<Vec3> displacement, std::span<Vec3> velocity) const = 0;

  // Motions that are, over their current window, a sum of K fixed fields times functions
  // of time, d(X, t) = sum_k c_k(t) f_k(X) and v(X, t) = sum_k c_k'(t) f_k(X) (the shell's
  // Hermite window: K = 4). A mover that is linear in the motion can then move its K fields
  // once per window and combine them per update. K = 0: not of this form.
  static constexpr int max_time_modes = 8;
  virtual int num_time_modes() const { return 0; }
  /// Changes whenever the fields f_k change (a new window); 0 for motions without modes.
  virtual std::uint64_t window_id() const { return 0; }
  /// f_k at the points registered under `handle`.
  virtual void evaluate_time_mode(int /*handle*/, int /*k*/, std::span<Vec3> /*field*/) const {}
  /// c_k(t) and c_k'(t), k < num_time_modes().
  virtual void time_coefficients(double /*time*/, std::span<double> /*c*/, std::span<double> /*dc*/) const {}
};

/// Panel deflection along `normal`: w(s, t) = sum_m A_m(t) sin(m pi s / L), s = (X - X_le).tangent
/// the distance from the panel's leading edge, zero outside 0 <= s <= L.
class PanelModesMotion final : public BoundaryMotion {
 public:
  struct Mode {
    int wave_number = 1;     ///< m
    TimeFunction amplitude;  ///< A_m(t) [m]
  };
  PanelModesMotion(Vec3 leading_edge, Vec3 tangent, double length, Vec3 normal, std::vector<Mode> modes);

  int register_points(std::span<const Vec3> initial_positions) override;
  void evaluate(int handle, double time, std::span<Vec3> displacement, std::span<Vec3> velocity) const override;

  /// Deflection shape factor at an initial position: sum over modes of sin(m pi s/L) weights.
  double deflection(const Vec3& X, double time) const;

 private:
  Vec3 leading_edge_, tangent_, normal_;
  double length_;
  std::vector<Mode> modes_;
  std::vector<std::vector<Vec3>> point_sets_;
};

/// A rigid translation d(t) of the whole interface (for tests: partition of unity).
class TranslationMotion final : public BoundaryMotion {
 public:
  TranslationMotion(Vec3 direction, TimeFunction amount);
  int register_points(std::span<const Vec3> initial_positions) override;
  void evaluate(int handle, double time, std::span<Vec3> displacement, std::span<Vec3> velocity) const override;

 private:
  Vec3 direction_;
  TimeFunction amount_;
  std::vector<std::size_t> sizes_;
};

}  // namespace shellflow::motion
