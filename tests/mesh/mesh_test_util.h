#pragma once
#include <filesystem>
#include <optional>

#include "shellflow/mesh/gmsh_io.h"

/// Meshing options with the given order, size factor and optional .msh output.
inline shellflow::mesh::MeshingOptions with_order(int order, double size_factor = 1.0,
                                                  std::optional<std::filesystem::path> msh = std::nullopt) {
  shellflow::mesh::MeshingOptions o;
  o.order = order;
  o.size_factor = size_factor;
  o.msh_output = std::move(msh);
  return o;
}
