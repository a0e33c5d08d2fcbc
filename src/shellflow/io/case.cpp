// The case reader: read_case() reads the sections in order through their readers
// (case_sections.h says which file reads which) and checks how they fit together;
// check_physical_groups(), and the helpers the section readers share.
#include "shellflow/io/case.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <map>
#include <utility>

#include "shellflow/core/error.h"
#include "shellflow/io/case_sections.h"

namespace shellflow::io {

namespace fs = std::filesystem;

namespace {

/// Names used in output file names and CSV headers: [A-Za-z0-9_.-]+.
bool is_valid_name(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '-';
  });
}

using detail::read_fluid;
using detail::read_meshes;
using detail::read_motion;
using detail::read_name;
using detail::read_output;
using detail::read_probes;
using detail::read_shell;
using detail::read_time;
using detail::require_mesh;

Case read_case(const YamlNode& root) {
  Case c;
  c.file = root.file();
  c.name = read_name(root, "name");
  c.description = root.optional<std::string>("description", {});
  c.meshes = read_meshes(root);
  if (auto node = root.optional_child("shell")) {
    require_mesh(*node, c.meshes, "shell");
    c.shell = read_shell(*node, c.group_references);
  }
  if (auto node = root.optional_child("fluid")) {
    c.fluid = read_fluid(*node, c.group_references);
    if (c.fluid->model == FluidModelType::euler) require_mesh(*node, c.meshes, "fluid");
  }
  if (auto node = root.optional_child("motion")) {
    require_mesh(*node, c.meshes, "fluid");
    c.motion = read_motion(*node, c.meshes, c.group_references);
  }
  if (auto node = root.optional_child("time")) c.time = read_time(*node);
  if (auto node = root.optional_child("coupling")) {
    c.coupling = detail::read_coupling(*node, c.meshes, c.group_references);
    detail::check_coupled_case(c);
  }
  if (c.shell && c.shell->analysis && c.shell->analysis->type == ShellAnalysisType::dynamic &&
      !(c.time && c.time->step > 0)) {
    throw_at(c.shell->analysis->where, "a dynamic analysis needs a 'time' section (end, step)");
  }
  if (c.motion && !(c.time && c.time->step > 0)) {
    throw_at(c.motion->where, "a mesh-motion run needs a 'time' section (end, step)");
  }
  if (c.motion && !c.coupling && !c.motion->prescribed) {
    throw_at(c.motion->where,
             "a mesh-motion run without a 'coupling' section needs 'prescribed' (the "
             "boundary motion); add it, or a 'coupling' section to let the shell drive it");
  }
  if (c.fluid && c.fluid->analysis && c.fluid->analysis->type == FluidAnalysisType::transient && !c.time) {
    throw_at(c.fluid->analysis->where,
             "a transient flow analysis needs a 'time' section (end; the step follows from cfl)");
  }
  if (c.fluid && c.fluid->mesh_motion) {
    if (c.motion) {
      throw_at(c.fluid->mesh_motion->where,
               "the fluid mesh is moved either by 'fluid.mesh_motion' (prescribed) or by the "
               "'motion' section (space mesh), not both; remove one");
    }
    for (const FluidBoundary& b : c.fluid->boundaries) {
      if (b.type == FluidBoundaryType::no_slip_wall && b.wall_velocity) {
        throw_at(b.where,
                 "on a moving mesh a no-slip wall moves with the mesh; remove its "
                 "'velocity' or the 'mesh_motion'");
      }
    }
    if (c.fluid->analysis && c.fluid->analysis->type == FluidAnalysisType::steady) {
      throw_at(c.fluid->mesh_motion->where,
               "a steady (local time stepping) analysis needs a fixed mesh; use type: transient "
               "or remove 'mesh_motion'");
    }
  }
  if (!c.coupling) {
    int solvers = (c.motion ? 1 : 0) + (c.shell && c.shell->analysis ? 1 : 0) + (c.fluid && c.fluid->analysis ? 1 : 0);
    if (solvers > 1) {
      throw_at(c.motion ? c.motion->where : c.fluid->analysis->where,
               "combining mesh motion, a shell analysis and a flow analysis is a coupled run: "
               "add a 'coupling' section (docs/case-format.md), or keep one of them");
    }
  }

  c.probes = read_probes(root, c.meshes, c.group_references);
  c.output = read_output(root, c.name);
  if (c.coupling) (void)response_probe(c);  // an unknown coupling.response.probe, before anything runs
  if (auto node = root.optional_child("study")) c.study = detail::read_study(*node, c);
  root.finish();
  c.digests = case_digests(root.yaml());
  std::stable_sort(c.group_references.begin(), c.group_references.end(),
                   [](const GroupReference& a, const GroupReference& b) { return a.where.line < b.where.line; });
  return c;
}

}  // namespace

namespace detail {

std::string join(const std::vector<std::string>& items, std::string_view sep) {
  return fmt::format("{}", fmt::join(items, sep));
}

std::string read_name(const YamlNode& node, std::string_view key) {
  std::string value = node.required<std::string>(key);
  if (!is_valid_name(value)) {
    node.fail(key, fmt::format("must contain only letters, digits, '_', '.' and '-', got '{}'", value));
  }
  return value;
}

void require_mesh(const YamlNode& section, const MeshesSection& meshes, std::string_view mesh) {
  if (!meshes.find(mesh)) {
    section.fail(fmt::format("needs a {} mesh; expected 'meshes.{}' with 'geo' or 'msh'", mesh, mesh));
  }
}

std::string read_group(const YamlNode& node, std::string_view mesh, std::vector<GroupReference>& refs) {
  std::string group = node.required<std::string>("group");
  if (group.empty()) node.fail("group", "expected a physical group name, got an empty string");
  refs.push_back({group, std::string(mesh), node.location("group")});
  return group;
}

Vec3 unit_vector(const YamlNode& node, std::string_view key, const Vec3& v) {
  const double n = v.norm();
  if (!(n > 0.0)) node.fail(key, "must be a non-zero vector [x, y, z], got [0, 0, 0]");
  return v / n;
}

}  // namespace detail

Case read_case(const fs::path& file, std::span<const KeyOverride> overrides) {
  return read_case(YamlNode::load_file(file, overrides));
}

Case read_case_string(std::string_view text, const fs::path& file, std::span<const KeyOverride> overrides) {
  return read_case(YamlNode::load_string(text, file, overrides));
}

void check_physical_groups(const Case& c, const GroupNamesOfMesh& groups_of_mesh) {
  std::map<std::string, std::vector<std::string>, std::less<>> groups;
  for (const GroupReference& ref : c.group_references) {
    auto it = groups.find(ref.mesh);
    if (it == groups.end()) it = groups.emplace(ref.mesh, groups_of_mesh(ref.mesh)).first;
    const std::vector<std::string>& available = it->second;
    if (std::find(available.begin(), available.end(), ref.group) != available.end()) continue;

    const MeshSpec* mesh = c.meshes.find(ref.mesh);
    std::string what = fmt::format("physical group '{}' not found in mesh '{}'", ref.group, ref.mesh);
    if (mesh) what += fmt::format(" ({})", mesh->as_written);
    if (available.empty()) {
      what += "; the mesh has no physical groups";
    } else {
      if (auto suggestion = closest_match(ref.group, available)) {
        what += fmt::format("; did you mean '{}'? available: {}", *suggestion, detail::join(available, ", "));
      } else {
        what += fmt::format("; available: {}", detail::join(available, ", "));
      }
    }
    throw_at(ref.where, what);
  }
}

}  // namespace shellflow::io
