#pragma once
// Internal to the case reader: the readers of the case file's sections and the helpers they
// share. One file per section, all in src/shellflow/io/:
//
//   case.cpp                  read_case(): the sections in order and how they fit together;
//                             check_physical_groups(); the shared helpers below
//   case_time_meshes.cpp      `meshes`, `time`, and the time functions other sections use
//   case_shell.cpp            `shell`
//   case_fluid.cpp            `fluid` (and SpaceTimeScalar's check)
//   case_motion.cpp           `motion`
//   case_coupling.cpp         `coupling`
//   case_probes.cpp           `probes`
//   case_probe_reference.cpp  `probes[i].reference`
//   case_output.cpp           `output`
//   case_study.cpp            `study`
//
// The structs of the shell, fluid and motion sections are declared in case_shell.h,
// case_fluid.h and case_motion.h (included by case.h), the others in case.h. case_names.h
// holds the names of the enumerations. (case_meshes.cpp does not read the case file: it
// meshes or loads the meshes it names.)
#include <string>
#include <string_view>
#include <vector>

#include "shellflow/io/case.h"
#include "shellflow/io/case_names.h"
#include "shellflow/io/yaml_reader.h"

namespace shellflow::io::detail {

// ---- helpers shared by the section readers ----------------------------------------------------
// Defined in case.cpp; read_time_function() in case_time_meshes.cpp.

/// `items` joined with `sep`.
std::string join(const std::vector<std::string>& items, std::string_view sep);
/// A name used in output file names and CSV headers (key `key`): [A-Za-z0-9_.-]+.
std::string read_name(const YamlNode& node, std::string_view key);
/// Fails at `section` unless the case has the mesh `mesh` ("fluid", "space", "shell").
void require_mesh(const YamlNode& section, const MeshesSection& meshes, std::string_view mesh);
/// A physical group name (key `group`): non-empty; recorded in `refs` for check_physical_groups().
std::string read_group(const YamlNode& node, std::string_view mesh, std::vector<GroupReference>& refs);
/// A direction: normalised; a zero vector is an error.
Vec3 unit_vector(const YamlNode& node, std::string_view key, const Vec3& v);
/// A time function `{type: ..., ...}` (docs/case-format.md "Time functions").
TimeFunction read_time_function(const YamlNode& node);

// ---- the sections, in the order read_case() reads them ------------------------------------------

/// The `meshes` section of `root` (required).
MeshesSection read_meshes(const YamlNode& root);
/// The `shell` section.
ShellSection read_shell(const YamlNode& node, std::vector<GroupReference>& refs);
/// The `fluid` section.
FluidSection read_fluid(const YamlNode& node, std::vector<GroupReference>& refs);
/// The `motion` section.
MotionSection read_motion(const YamlNode& node, const MeshesSection& meshes, std::vector<GroupReference>& refs);
/// The `time` section.
TimeSection read_time(const YamlNode& node);

/// The `coupling` section.
CouplingSection read_coupling(const YamlNode& node, const MeshesSection& meshes, std::vector<GroupReference>& refs);
/// What a coupled case needs of its other sections (a dynamic shell analysis, a flow model or
/// a mesh motion, ...). Throws InputError at the offending section.
void check_coupled_case(const Case& c);

/// The `probes` list of `root` (optional; names unique).
std::vector<Probe> read_probes(const YamlNode& root, const MeshesSection& meshes, std::vector<GroupReference>& refs);
/// A probe's `reference: {file, column, scale, label}` (case_probe_reference.cpp): the file
/// must be a CSV with a header that holds the column.
Probe::Reference read_probe_reference(const YamlNode& node);

/// The `output` section of `root` (optional; default directory out/<case_name>).
OutputSection read_output(const YamlNode& root, const std::string& case_name);

/// The `study` section (read after the others: it checks them).
StudySection read_study(const YamlNode& node, const Case& c);

}  // namespace shellflow::io::detail
