#pragma once
// Meshes from Gmsh: generate from a `.geo` file through the Gmsh C++ API, or read a
// `.msh` file (format 4.1, any order). Gmsh keeps one global model, so every call here
// takes a process-wide lock and leaves no model behind.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "shellflow/mesh/mesh.h"

namespace shellflow::mesh {

struct MeshingOptions {
  int order = 1;             ///< element order: 1, 2 or 3
  double size_factor = 1.0;  ///< multiplies every mesh size of the .geo (Mesh.MeshSizeFactor)
  int dim = -1;              ///< dimension to mesh; -1: the highest dimension of the geometry
  /// Also write the generated mesh here (`.msh` 4.1), when set.
  std::optional<std::filesystem::path> msh_output;
  bool verbose = false;  ///< let Gmsh print its progress
};

/// Meshes a `.geo` (or any geometry Gmsh opens) and returns the mesh of its highest
/// dimension. Throws InputError naming the file when Gmsh fails.
Mesh generate_mesh(const std::filesystem::path& geometry, const MeshingOptions& options, std::string mesh_name);

/// Reads a `.msh` file. Element order is whatever the file holds.
Mesh read_msh(const std::filesystem::path& msh, std::string mesh_name);

/// Names of the physical groups a `.geo` or `.msh` file defines, without meshing it.
std::vector<std::string> physical_group_names(const std::filesystem::path& file);

}  // namespace shellflow::mesh
