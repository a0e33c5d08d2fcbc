// The `motion` section of a case file: how the fluid mesh follows the moving boundary.
#include <fmt/format.h>

#include <array>
#include <string_view>
#include <utility>

#include "shellflow/core/error.h"
#include "shellflow/io/case_sections.h"

namespace shellflow::io {

namespace {

std::vector<std::string> read_group_list(const YamlNode& node, std::string_view key,
                                         const std::vector<std::string_view>& meshes,
                                         std::vector<GroupReference>& refs) {
  std::vector<std::string> groups;
  for (const YamlNode& item : node.optional_list(key)) {
    std::string group = item.as<std::string>();
    if (group.empty()) item.fail("expected a physical group name, got an empty string");
    for (auto mesh : meshes) refs.push_back({group, std::string(mesh), item.location()});
    groups.push_back(std::move(group));
  }
  return groups;
}

}  // namespace

namespace detail {

MotionSection read_motion(const YamlNode& node, const MeshesSection& meshes, std::vector<GroupReference>& refs) {
  MotionSection m;
  m.where = node.location();
  m.method = read_enum(node, "method", kMotionMethods, MotionMethod::space_mesh);
  if (m.method == MotionMethod::space_mesh) require_mesh(node, meshes, "space");
  std::vector<std::string_view> group_meshes{"fluid"};
  if (m.method == MotionMethod::space_mesh) group_meshes.push_back("space");
  m.interface_groups = read_group_list(node, "interface_groups", group_meshes, refs);
  if (m.interface_groups.empty()) {
    node.fail("interface_groups", "expected a list of the moving boundary's physical groups");
  }
  m.fixed_groups = read_group_list(node, "fixed_groups", group_meshes, refs);
  m.sliding_groups = read_group_list(node, "sliding_groups", group_meshes, refs);
  m.interface_exponent = node.optional<double>("interface_exponent", 4.0, Range::positive());
  m.fixed_exponent = node.optional<double>("fixed_exponent", 4.0, Range::positive());
  m.weighting = read_enum(node, "weighting", kMotionWeightings, MotionWeighting::plain);
  if (auto p = node.optional_child("prescribed")) {
    PanelModesSpec spec;
    spec.where = p->location();
    const std::string type = p->choice("type", {"panel_modes"});
    (void)type;
    spec.leading_edge = p->vec3("leading_edge");
    spec.direction = unit_vector(*p, "direction", p->vec3("direction", Vec3::UnitX()));
    spec.length = p->required<double>("length", Range::positive(), "m");
    spec.normal = unit_vector(*p, "normal", p->vec3("normal", Vec3::UnitY()));
    for (const YamlNode& item : p->list("modes")) {
      item.expect_map();
      PanelModesSpec::Mode mode;
      mode.wave_number = item.optional<int>("wave_number", 1, Range::at_least(1));
      mode.amplitude = read_time_function(item.child("amplitude"));
      item.finish();
      spec.modes.push_back(std::move(mode));
    }
    p->finish();
    m.prescribed = std::move(spec);
  }
  node.finish();
  return m;
}

}  // namespace detail

std::string_view to_string(MotionMethod m) { return detail::name_of(detail::kMotionMethods, m); }
std::string_view to_string(MotionWeighting w) { return detail::name_of(detail::kMotionWeightings, w); }

}  // namespace shellflow::io
