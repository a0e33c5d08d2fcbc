#pragma once
// The reference panel strip of shell-references.md as a ShellModel, and the cubic case
// meshes of cases/shell (tests only).
#include <filesystem>
#include <string>

#include "shellflow/mesh/gmsh_io.h"
#include "shellflow/shell/shell_model.h"

namespace shellflow::shell {

/// A case mesh of cases/shell meshed at order 3 (10-node triangles).
inline mesh::Mesh cubic_mesh(const std::string& file) {
  mesh::MeshingOptions meshing;
  meshing.order = 3;
  return mesh::generate_mesh(std::filesystem::path(SHELLFLOW_SOURCE_DIR) / "cases/shell" / file, meshing, "shell");
}

inline ShellModel reference_strip() {
  ShellSection section;
  section.thickness = 1.35e-3;
  section.material = {77.28e9, 0.33, 2710.0};
  ShellModel model(cubic_mesh("strip_20x1.geo"), section);
  model.add_support(Support::clamped("leading_edge"));
  model.add_support(Support::clamped("trailing_edge"));
  model.add_support(Support::symmetry_plane("sides", 2));  // long edges z = 0, 0.025
  return model;
}

}  // namespace shellflow::shell
