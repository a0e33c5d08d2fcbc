#pragma once
// Internal to the case reader: the readers of case-file sections that live in their own
// files (case_coupling.cpp, case_study.cpp), and the helpers they share with case.cpp.
#include <string>
#include <string_view>
#include <vector>

#include "shellflow/io/case.h"
#include "shellflow/io/yaml_reader.h"

namespace shellflow::io::detail {

/// A physical group name (key `group`): non-empty; recorded in `refs` for check_physical_groups().
std::string read_group(const YamlNode& node, std::string_view mesh, std::vector<GroupReference>& refs);
/// A direction: normalised; a zero vector is an error.
Vec3 unit_vector(const YamlNode& node, std::string_view key, const Vec3& v);
/// A time function `{type: ..., ...}` (docs/case-format.md "Time functions").
TimeFunction read_time_function(const YamlNode& node);

/// A probe's `reference: {file, column, scale, label}` (case_reference.cpp): the file must be
/// a CSV with a header that holds the column.
Probe::Reference read_probe_reference(const YamlNode& node);

/// The `coupling` section.
CouplingSection read_coupling(const YamlNode& node, const MeshesSection& meshes,
                              std::vector<GroupReference>& refs);
/// What a coupled case needs of its other sections (a dynamic shell analysis, a flow model or
/// a mesh motion, ...). Throws InputError at the offending section.
void check_coupled_case(const Case& c);

/// The `study` section (read after the others: it checks them).
StudySection read_study(const YamlNode& node, const Case& c);

}  // namespace shellflow::io::detail
