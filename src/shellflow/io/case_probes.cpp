// The `probes` section of a case file, and the quantities a probe may record.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <map>
#include <string_view>
#include <utility>

#include "shellflow/core/error.h"
#include "shellflow/io/case_sections.h"

namespace shellflow::io {

namespace {

using detail::join;
using detail::read_group;
using detail::read_name;

constexpr std::array<ProbeQuantity, 14> kProbeQuantities = {{
    {"shell", "displacement", true},
    {"shell", "velocity", true},
    {"shell", "acceleration", true},
    {"shell", "position", true},
    {"fluid", "density", false},
    {"fluid", "pressure", false},
    {"fluid", "temperature", false},
    {"fluid", "mach", false},
    {"fluid", "velocity", true},
    {"fluid", "momentum", true},
    {"fluid", "energy", false},
    {"fluid", "mesh_velocity", true},
    {"space", "displacement", true},
    {"space", "velocity", true},
}};

Probe read_probe(const YamlNode& item, const MeshesSection& meshes, std::vector<GroupReference>& refs) {
  item.expect_map();
  Probe p;
  p.where = item.location();
  p.name = read_name(item, "name");
  if (p.name == "time") {
    item.fail("name",
              "'time' is reserved for the time column of probes.csv; expected another "
              "name");
  }

  p.field = item.required<std::string>("field");
  const auto dot = p.field.find('.');
  p.mesh = p.field.substr(0, dot);
  p.quantity = dot == std::string::npos ? std::string() : p.field.substr(dot + 1);
  if (dot == std::string::npos ||
      std::find(std::begin(kMeshKeys), std::end(kMeshKeys), p.mesh) == std::end(kMeshKeys)) {
    item.fail("field", fmt::format("expected 'MESH.QUANTITY' with MESH one of fluid, space, "
                                   "shell, got '{}'",
                                   p.field));
  }
  const ProbeQuantity* quantity = nullptr;
  std::vector<std::string> fields;
  for (const auto& q : probe_quantities()) {
    if (q.mesh != p.mesh) continue;
    fields.push_back(fmt::format("{}.{}", q.mesh, q.quantity));
    if (q.quantity == p.quantity) quantity = &q;
  }
  if (!quantity) {
    std::string what = fmt::format("unknown field '{}'; ", p.field);
    if (auto suggestion = closest_match(p.field, fields)) {
      what += fmt::format("did you mean '{}'? (one of: {})", *suggestion, join(fields, ", "));
    } else {
      what += fmt::format("expected one of: {}", join(fields, ", "));
    }
    item.fail("field", what);
  }
  if (!meshes.find(p.mesh)) {
    item.fail("field", fmt::format("the case has no {} mesh; expected 'meshes.{}'", p.mesh, p.mesh));
  }

  if (quantity->is_vector) {
    p.component = detail::read_enum(item, "component", detail::kVectorProbeComponents, ProbeComponent::magnitude);
  } else {
    p.component = ProbeComponent::scalar;
    if (item.has("component")) {
      item.fail("component", fmt::format("applies only to vector fields; '{}' is a scalar", p.field));
    }
  }

  const int given = int{item.has("point")} + int{item.has("node")} + int{item.has("group")};
  if (given == 0) item.fail_missing({"point", "node", "group"});
  if (given > 1) item.fail("give only one of 'point', 'node', 'group'");
  if (item.has("point")) {
    p.location = ProbeLocation::point;
    p.point = item.vec3("point");
  } else if (item.has("node")) {
    p.location = ProbeLocation::node;
    p.node = item.required<Index>("node", Range::non_negative());
  } else {
    p.location = ProbeLocation::group;
    p.group = read_group(item, p.mesh, refs);
  }
  if (p.location == ProbeLocation::group) {
    p.reduce = detail::read_enum(item, "reduce", detail::kProbeReductions, ProbeReduce::mean);
  } else if (item.has("reduce")) {
    item.fail("reduce", "applies only to probes on a 'group'");
  }
  if (auto r = item.optional_child("reference")) p.reference = detail::read_probe_reference(*r);
  item.finish();
  return p;
}

}  // namespace

namespace detail {

std::vector<Probe> read_probes(const YamlNode& root, const MeshesSection& meshes, std::vector<GroupReference>& refs) {
  std::vector<Probe> probes;
  std::map<std::string, int> first_line;  // name -> line where it was first used
  for (const YamlNode& item : root.optional_list("probes")) {
    Probe p = read_probe(item, meshes, refs);
    const auto [it, inserted] = first_line.emplace(p.name, item.location("name").line);
    if (!inserted) {
      item.fail("name", fmt::format("duplicate probe name '{}' (first used at line {}); "
                                    "expected unique names",
                                    p.name, it->second));
    }
    probes.push_back(std::move(p));
  }
  return probes;
}

}  // namespace detail

std::span<const ProbeQuantity> probe_quantities() { return kProbeQuantities; }

std::string_view to_string(ProbeComponent c) { return detail::name_of(detail::kProbeComponents, c); }
std::string_view to_string(ProbeLocation l) { return detail::name_of(detail::kProbeLocations, l); }
std::string_view to_string(ProbeReduce r) { return detail::name_of(detail::kProbeReductions, r); }

}  // namespace shellflow::io
