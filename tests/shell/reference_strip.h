#pragma once
// The reference panel strip of shell-references.md as a ShellModel (tests only).
#include <filesystem>

#include "shellflow/mesh/gmsh_io.h"
#include "shellflow/shell/shell_model.h"

namespace shellflow::shell {

inline ShellModel reference_strip() {
  mesh::MeshingOptions meshing;
  meshing.order = 3;
  ShellSection section;
  section.thickness = 1.35e-3;
  section.material = {77.28e9, 0.33, 2710.0};
  ShellModel model(mesh::generate_mesh(std::filesystem::path(SHELLFLOW_SOURCE_DIR) / "cases/shell/strip_20x1.geo",
                                       meshing, "shell"),
                   section);
  model.add_support(Support::clamped("leading_edge"));
  model.add_support(Support::clamped("trailing_edge"));
  model.add_support(Support::symmetry_plane("sides", 2));  // long edges z = 0, 0.025
  return model;
}

}  // namespace shellflow::shell
