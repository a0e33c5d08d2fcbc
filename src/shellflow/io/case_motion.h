#pragma once
// The `motion` section of a case file as plain structs, part of case.h (which includes it;
// include case.h). Read by case_motion.cpp; the keys are documented in docs/case-format.md.
#include <optional>
#include <string>
#include <vector>

#include "shellflow/core/time_function.h"
#include "shellflow/core/types.h"
#include "shellflow/io/yaml_reader.h"

namespace shellflow::io {

/// How the fluid mesh follows the moving boundary.
enum class MotionMethod {
  space_mesh,  ///< the coarse cubic space mesh (the paper's method)
  direct_idw,  ///< inverse-distance weighting on every fluid node (baseline)
  laplace,     ///< Laplacian smoothing on the fluid mesh (baseline)
};
enum class MotionWeighting { plain, area };

/// A prescribed panel deflection w(s, t) = sum_m A_m(t) sin(m pi s / L) along `normal`, s the
/// distance from `leading_edge` along `direction` (0 <= s <= length).
struct PanelModesSpec {
  Vec3 leading_edge = Vec3::Zero();  ///< [m]
  Vec3 direction = Vec3::UnitX();    ///< unit vector along the panel
  double length = 0.0;               ///< [m], > 0
  Vec3 normal = Vec3::UnitY();       ///< unit vector of the deflection
  struct Mode {
    int wave_number = 1;     ///< m >= 1
    TimeFunction amplitude;  ///< A_m(t) [m]
  };
  std::vector<Mode> modes;
  SourceLocation where;
};

struct MotionSection {
  MotionMethod method = MotionMethod::space_mesh;
  std::vector<std::string> interface_groups;  ///< moving boundary (fluid and space mesh)
  std::vector<std::string> fixed_groups;
  std::vector<std::string> sliding_groups;  ///< symmetry / slip planes
  double interface_exponent = 4.0;          ///< e1 of the IDW weights
  double fixed_exponent = 4.0;              ///< e2
  MotionWeighting weighting = MotionWeighting::plain;
  /// The boundary motion when no shell solver drives it.
  std::optional<PanelModesSpec> prescribed;
  SourceLocation where;
};

}  // namespace shellflow::io
