#pragma once
// The meshes of a case: generated from their `.geo` through Gmsh or read from `.msh`.
#include <filesystem>
#include <optional>
#include <string_view>
#include <vector>

#include "shellflow/io/case.h"
#include "shellflow/mesh/mesh.h"
#include "shellflow/mesh/quality.h"

namespace shellflow::io {

struct CaseMeshes {
  std::optional<mesh::Mesh> fluid;
  std::optional<mesh::Mesh> space;
  std::optional<mesh::Mesh> shell;

  /// nullptr when the case has no mesh of that key.
  const mesh::Mesh* find(std::string_view key) const;
  /// The meshes present, in the order fluid, space, shell.
  std::vector<const mesh::Mesh*> all() const;
};

/// Meshes (`.geo`) or reads (`.msh`) every mesh of the case. When `msh_dir` is set, each
/// mesh is also saved there as `<key>.msh` (format 4.1), and a mesh of a `.geo` with its
/// cache `<key>.msh.cache`: a later call with the same `msh_dir` reads the mesh from that
/// cache, without Gmsh, when the `.geo` (and every file it includes or merges), the meshing
/// options, the Gmsh version and shellflow's version are unchanged (docs/output.md). A cache
/// that does not match, is damaged or unreadable is ignored and the mesh generated again.
/// `cache_dir` (used only when `msh_dir` is not set, e.g. by a restart, which saves no
/// meshes): a folder whose caches are read but not written. Checks that every physical group
/// the case names exists, that each mesh has the expected dimension (fluid and space:
/// tetrahedra, shell: triangles; space mesh of order 3) and that no tetrahedron is
/// inverted. Throws InputError naming the case file's line and the fix.
CaseMeshes load_case_meshes(const Case& c, const std::optional<std::filesystem::path>& msh_dir,
                            const std::optional<std::filesystem::path>& cache_dir = std::nullopt);

/// Checks the case's physical-group references against its mesh files without meshing
/// them (Gmsh reads the groups from the `.geo` or `.msh`).
void check_case_groups(const Case& c);

/// Size and quality figures of one mesh, as `shellflow mesh` reports them.
struct MeshReport {
  std::string key;
  std::string source;
  Index nodes = 0;
  Index elements = 0;
  std::string element_type;  ///< "tet4", "tet20", "tri10", ...
  int gmsh_type = 0;
  mesh::QualitySummary quality;
};
MeshReport report_mesh(const mesh::Mesh& m);

/// One JSON object: {"fluid": {"nodes": .., "elements": .., "element_type": "tet4",
/// "gmsh_type": 4, "min_quality": .., "mean_quality": .., "inverted": 0, "source": ".."}, ...}
std::string reports_to_json(const std::vector<MeshReport>& reports);

}  // namespace shellflow::io
