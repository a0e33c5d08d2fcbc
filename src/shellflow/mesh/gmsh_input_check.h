#pragma once
// Checks run on every file before it is handed to Gmsh, so that reading a case never runs
// what a geometry file asks for and a damaged mesh file is an error instead of a crash.
//
// - A `.geo` script (and every file it includes or merges, and the `FILE.opt` option file
//   Gmsh merges after any file it opens) is scanned, comments and strings skipped: the
//   commands that run programs (System, SystemCall, NonBlockingSystemCall, OnelabRun), write
//   files (Print, Save, CreateDir, Printf(...) > "file") or end the process (Exit) are
//   refused, and Include/Merge/ShapeFromFile must name a quoted relative file inside the
//   folder of the top-level file.
// - A `.msh` file must be a Gmsh mesh: `$MeshFormat` first, version 4.1 ASCII, and its
//   sections ($PhysicalNames, $Entities, $Nodes, $Elements) complete and consistent
//   (counts, tags, element node counts), checked before Gmsh 4.8 reads it (Gmsh crashes on
//   some damaged files).
//
// Every problem is one InputError line naming the file, the line and the fix.
#include <filesystem>
#include <string_view>
#include <vector>

namespace shellflow::mesh {

/// Checks any file before gmsh::open: a `.msh` as a mesh, a `.geo` as a script, STEP/IGES/
/// BREP files pass; anything else is refused. Also checks `FILE.opt` when it exists.
void check_gmsh_input(const std::filesystem::path& file);

/// Checks `file` as check_gmsh_input does and returns every file Gmsh reads when it opens it:
/// the file, the scripts, meshes and CAD files it includes or merges (recursively, in the
/// order met) and the option files (`FILE.opt`). The mesh cache digests their bytes.
std::vector<std::filesystem::path> gmsh_input_files(const std::filesystem::path& file);

/// Validates the structure of a `.msh` file (format 4.1 ASCII).
void check_msh_file(const std::filesystem::path& file);
/// The same check of a `.msh` file's text (`file` names it in messages).
void check_msh_text(std::string_view text, const std::filesystem::path& file);

/// Scans the option files Gmsh merges after opening `file` (`FILE.opt`, `FILE.opt.opt`...).
void check_gmsh_option_files(const std::filesystem::path& file);

/// Number of nodes of a Gmsh element type (1 line2 ... 31 tet56, 92/93 hexahedra), 0 when
/// the type is unknown; `dim` receives its dimension.
int msh_element_node_count(int gmsh_type, int* dim = nullptr);

}  // namespace shellflow::mesh
