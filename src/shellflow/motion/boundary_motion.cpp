#include "shellflow/motion/boundary_motion.h"

#include <cmath>
#include <numbers>

#include "shellflow/core/error.h"

namespace shellflow::motion {

PanelModesMotion::PanelModesMotion(Vec3 leading_edge, Vec3 tangent, double length, Vec3 normal, std::vector<Mode> modes)
    : leading_edge_(leading_edge),
      tangent_(tangent.normalized()),
      normal_(normal.normalized()),
      length_(length),
      modes_(std::move(modes)) {
  if (!(length > 0.0)) throw InputError(fmt::format("panel length must be > 0, got {}", length));
}

int PanelModesMotion::register_points(std::span<const Vec3> initial_positions) {
  point_sets_.emplace_back(initial_positions.begin(), initial_positions.end());
  return static_cast<int>(point_sets_.size()) - 1;
}

void PanelModesMotion::evaluate(int handle, double time, std::span<Vec3> displacement, std::span<Vec3> velocity) const {
  const auto& points = point_sets_.at(static_cast<std::size_t>(handle));
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double s = (points[i] - leading_edge_).dot(tangent_);
    double w = 0.0, w_dot = 0.0;
    if (s >= 0.0 && s <= length_) {
      for (const Mode& m : modes_) {
        const double shape = std::sin(m.wave_number * std::numbers::pi * s / length_);
        w += m.amplitude.value(time) * shape;
        w_dot += m.amplitude.derivative(time) * shape;
      }
    }
    displacement[i] = w * normal_;
    velocity[i] = w_dot * normal_;
  }
}

double PanelModesMotion::deflection(const Vec3& X, double time) const {
  const double s = (X - leading_edge_).dot(tangent_);
  if (s < 0.0 || s > length_) return 0.0;
  double w = 0.0;
  for (const Mode& m : modes_) w += m.amplitude.value(time) * std::sin(m.wave_number * std::numbers::pi * s / length_);
  return w;
}

TranslationMotion::TranslationMotion(Vec3 direction, TimeFunction amount)
    : direction_(direction), amount_(std::move(amount)) {}

int TranslationMotion::register_points(std::span<const Vec3> initial_positions) {
  sizes_.push_back(initial_positions.size());
  return static_cast<int>(sizes_.size()) - 1;
}

void TranslationMotion::evaluate(int handle, double time, std::span<Vec3> displacement,
                                 std::span<Vec3> velocity) const {
  const std::size_t n = sizes_.at(static_cast<std::size_t>(handle));
  for (std::size_t i = 0; i < n; ++i) {
    displacement[i] = amount_.value(time) * direction_;
    velocity[i] = amount_.derivative(time) * direction_;
  }
}

}  // namespace shellflow::motion
