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
  bool verbose = false;                         ///< let Gmsh print its progress
  std::string size_factor_key = "size_factor";  ///< the case key of size_factor, for messages
};

/// Meshes a `.geo` (or any geometry Gmsh opens) and returns the mesh of its highest
/// dimension. Throws InputError naming the file when Gmsh fails.
Mesh generate_mesh(const std::filesystem::path& geometry, const MeshingOptions& options, std::string mesh_name);

/// The size of a mesh before it is made: below this size factor a mesh is first made at
/// factors 1 and 0.5 (at most 14 % of the cost of the mesh asked), and the count at the factor
/// asked extrapolated from them. At 0.25 and above a mesh is at most 64 times the case's own.
inline constexpr double kSizeFactorProbedBelow = 0.25;

struct MeshSizeEstimate {
  double elements = 0.0;       ///< estimated elements at the factor asked (0: not estimated)
  double at_factor_one = 0.0;  ///< elements at size factor 1
  double exponent = 0.0;       ///< count ~ factor^-exponent, from factors 1 and 0.5
  double limit = 0.0;          ///< elements this machine's memory holds (physical memory / bytes per element)
};

/// The estimate (elements 0 for a size factor >= kSizeFactorProbedBelow: no probe).
MeshSizeEstimate estimate_mesh_size(const std::filesystem::path& geometry, const MeshingOptions& options);

/// Throws InputError naming the geometry, the size factor's key, the estimate and the
/// smallest factor the machine holds when the estimate exceeds the machine's memory
/// (`shellflow check`; generate_mesh checks the same before it meshes).
void check_mesh_size_of(const std::filesystem::path& geometry, const MeshingOptions& options);

/// Reads a `.msh` file. Element order is whatever the file holds.
Mesh read_msh(const std::filesystem::path& msh, std::string mesh_name);

/// Names of the physical groups a `.geo` or `.msh` file defines, without meshing it.
std::vector<std::string> physical_group_names(const std::filesystem::path& file);

}  // namespace shellflow::mesh
