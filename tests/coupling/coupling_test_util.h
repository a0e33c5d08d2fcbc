#pragma once
// Shared set-up of the coupling tests: the panel-flutter meshes (generated once per process)
// and the reference panel's shell model.
#include <filesystem>

#include "shellflow/core/version.h"
#include "shellflow/coupling/linear_flutter.h"
#include "shellflow/mesh/gmsh_io.h"
#include "shellflow/shell/shell_model.h"

namespace coupling_test {

inline const std::filesystem::path cases_dir = std::filesystem::path(shellflow::source_dir) / "cases";

inline shellflow::mesh::Mesh generate(const char* geo, int order, const char* name, double size_factor = 1.0) {
  shellflow::mesh::MeshingOptions options;
  options.order = order;
  options.size_factor = size_factor;
  return shellflow::mesh::generate_mesh(cases_dir / "panel_flutter" / geo, options, name);
}
/// The flutter case's fluid slab at size factor 2 (coarse, for speed).
inline const shellflow::mesh::Mesh& coarse_fluid() {
  static const auto m = generate("fluid_slab.geo", 1, "fluid", 2.0);
  return m;
}
inline const shellflow::mesh::Mesh& space() {
  static const auto m = generate("space_mesh.geo", 3, "space");
  return m;
}
inline const shellflow::mesh::Mesh& strip() {
  static const auto m = generate("panel_strip.geo", 3, "shell");
  return m;
}

/// The aluminium panel of the paper (1.35 mm) on a shell mesh.
inline shellflow::shell::ShellModel panel_model(const shellflow::mesh::Mesh& mesh) {
  shellflow::shell::ShellSection section;
  section.thickness = 1.35e-3;
  section.material = {77.28e9, 0.33, 2710.0};
  return shellflow::shell::ShellModel(mesh, section);
}

/// The flutter setting of the paper's aluminium (1.35 mm) under its air (0.339 kg/m^3, 28 kPa)
/// for a panel of streamwise length `length` at `mach`.
inline shellflow::coupling::FlutterSetting panel_flutter_setting(double length, double mach, bool damping) {
  constexpr double h = 1.35e-3, E = 77.28e9, nu = 0.33;
  shellflow::coupling::FlutterSetting s;
  s.length = length;
  s.bending_stiffness = E * h * h * h / (12.0 * (1.0 - nu * nu));
  s.density = 0.339;
  s.pressure = 28000.0;
  s.mach = mach;
  s.aerodynamic_damping = damping;
  return s;
}

}  // namespace coupling_test
