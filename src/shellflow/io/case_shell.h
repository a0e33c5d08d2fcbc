#pragma once
// The `shell` section of a case file as plain structs, part of case.h (which includes it;
// include case.h). Read by case_shell.cpp; the keys are documented in docs/case-format.md.
#include <optional>
#include <string>
#include <vector>

#include "shellflow/core/time_function.h"
#include "shellflow/core/types.h"
#include "shellflow/io/yaml_reader.h"

namespace shellflow::io {

struct Material {
  double young_modulus = 0.0;  ///< E [Pa], > 0
  double poisson_ratio = 0.0;  ///< nu [-], -1 < nu < 0.5
  double density = 0.0;        ///< rho [kg/m^3], >= 0
};

enum class SupportType {
  clamped,
  simply_supported,  ///< soft: positions fixed, directors free
  symmetry,
  sliding,
  prescribed,
  simply_supported_hard,  ///< positions fixed and the director kept normal to the edge
};

struct Support {
  std::string group;  ///< physical group of the shell mesh
  SupportType type = SupportType::clamped;
  Vec3 direction = Vec3::Zero();  ///< `sliding` only: unit vector of the allowed motion
  bool clamp_director = true;     ///< `sliding` only: director fixed (clamped-sliding)
  Vec3 normal = Vec3::Zero();     ///< `symmetry` only: unit normal of the symmetry plane
  /// `prescribed` only: x = X + f(t) d and, with a rotation axis, G = R(g(t)) V.
  Vec3 displacement = Vec3::Zero();                           ///< d [m]
  std::optional<TimeFunction> displacement_history;           ///< f; absent: the analysis' load factor
  Vec3 rotation_axis = Vec3::Zero();                          ///< unit axis, or zero (director free)
  TimeFunction rotation_angle = TimeFunction::constant(0.0);  ///< g [rad]
  SourceLocation where;                                       ///< the list item `shell.supports[i]`
};

enum class ShellLoadType { line, point, edge_couple, pressure, gravity, surface };

/// A load at load factor 1 (static) or scaled by the analysis' load function (dynamic).
struct ShellLoad {
  ShellLoadType type = ShellLoadType::line;
  std::string group;           ///< line, edge_couple: a line group; pressure: a surface
                               ///< group or empty (the whole shell)
  Vec3 vector = Vec3::Zero();  ///< line: force per length [N/m]; point: force [N];
                               ///< gravity: acceleration [m/s^2]; edge_couple: axis (unit);
                               ///< surface: traction per reference area [Pa]
  double value = 0.0;          ///< edge_couple: moment per length [N]; pressure [Pa]
  Vec3 point = Vec3::Zero();   ///< point: where (the nearest shell node takes the force)
  SourceLocation where;
};

enum class ShellAnalysisType { static_load, dynamic, modal };

/// How a static analysis follows the equilibrium path.
enum class PathControl {
  load,          ///< equal load increments
  displacement,  ///< equal increments of one displacement component (through load limits)
  arc_length,    ///< Crisfield's cylindrical arc length (through load and displacement limits)
};
enum class TimeScheme { newmark, midpoint };

struct ShellAnalysis {
  ShellAnalysisType type = ShellAnalysisType::static_load;
  int steps = 10;  ///< static: increments (arc length: at most this many)
  PathControl control = PathControl::load;
  /// control: displacement: the controlled component of a node or of a group's mean.
  std::string controlled_group;
  Index controlled_node = -1;
  int controlled_component = 2;                              ///< 0, 1, 2 = x, y, z
  double final_displacement = 0.0;                           ///< [m] displacement control: value at the last step
  double initial_load_increment = 0.1;                       ///< arc length: first load-factor increment
  double final_load_factor = 1.0;                            ///< arc length: stop once reached
  TimeFunction load_function = TimeFunction::constant(1.0);  ///< dynamic: load factor(t)
  double mass_damping = 0.0;                                 ///< dynamic: c_m in C = c_m M [1/s]
  TimeScheme scheme = TimeScheme::newmark;                   ///< dynamic
  bool modified_newton = false;    ///< load control, dynamic: keep the iteration matrix (NewtonOptions::modified)
  int modes = 10;                  ///< modal: number of natural frequencies and modes (1..200)
  double modal_tolerance = 1e-8;   ///< modal: ModalOptions::tolerance (relative eigenvalue change)
  int modal_max_iterations = 300;  ///< modal: ModalOptions::max_iterations
  SourceLocation where;
};

struct ShellSection {
  double thickness = 0.0;  ///< h [m], > 0
  Material material;
  std::vector<Support> supports;
  std::vector<ShellLoad> loads;
  std::optional<ShellAnalysis> analysis;  ///< absent: the shell is not solved
};

}  // namespace shellflow::io
