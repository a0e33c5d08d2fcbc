#include "shellflow/mesh/mesh.h"

#include <algorithm>
#include <array>

#include "shellflow/core/error.h"

namespace shellflow::mesh {
namespace {

constexpr std::array<ElementInfo, 10> element_table{{
    {ElementType::point, 0, 0, 1, 1, "point", "point"},
    {ElementType::line2, 1, 1, 2, 2, "line2", "2-node line"},
    {ElementType::line3, 1, 2, 3, 2, "line3", "3-node line"},
    {ElementType::line4, 1, 3, 4, 2, "line4", "4-node line"},
    {ElementType::tri3, 2, 1, 3, 3, "tri3", "3-node triangle"},
    {ElementType::tri6, 2, 2, 6, 3, "tri6", "6-node triangle"},
    {ElementType::tri10, 2, 3, 10, 3, "tri10", "10-node triangle"},
    {ElementType::tet4, 3, 1, 4, 4, "tet4", "4-node tetrahedron"},
    {ElementType::tet10, 3, 2, 10, 4, "tet10", "10-node tetrahedron"},
    {ElementType::tet20, 3, 3, 20, 4, "tet20", "20-node tetrahedron"},
}};

const ElementInfo* find_info(int gmsh_type) {
  for (const auto& info : element_table) {
    if (static_cast<int>(info.type) == gmsh_type) return &info;
  }
  return nullptr;
}

}  // namespace

bool is_supported_element_type(int gmsh_type) { return find_info(gmsh_type) != nullptr; }

const ElementInfo& element_info(int gmsh_type) {
  if (const auto* info = find_info(gmsh_type)) return *info;
  throw_input_error(
      "Gmsh element type {} is not supported; shellflow uses 3/6/10-node triangles (types 2, 9, "
      "21) and 4/10/20-node tetrahedra (types 4, 11, 29)",
      gmsh_type);
}

const ElementInfo& element_info(ElementType type) { return element_info(static_cast<int>(type)); }

ElementType facet_type(ElementType type) {
  switch (type) {
    case ElementType::tet4:
      return ElementType::tri3;
    case ElementType::tet10:
      return ElementType::tri6;
    case ElementType::tet20:
      return ElementType::tri10;
    case ElementType::tri3:
      return ElementType::line2;
    case ElementType::tri6:
      return ElementType::line3;
    case ElementType::tri10:
      return ElementType::line4;
    case ElementType::line2:
    case ElementType::line3:
    case ElementType::line4:
      return ElementType::point;
    case ElementType::point:
      break;
  }
  throw Error("facet_type: a point has no facets");
}

const PhysicalGroup* Mesh::find_group(std::string_view group_name) const {
  auto it = std::find_if(groups.begin(), groups.end(), [&](const PhysicalGroup& g) { return g.name == group_name; });
  return it == groups.end() ? nullptr : &*it;
}

const PhysicalGroup& Mesh::group(std::string_view group_name) const {
  if (const auto* g = find_group(group_name)) return *g;
  throw_input_error("{}: physical group '{}' not found in the {} mesh; available: {}", source, group_name, name,
                    fmt::join(group_names(), ", "));
}

std::vector<std::string> Mesh::group_names() const {
  std::vector<std::string> names;
  names.reserve(groups.size());
  for (const auto& g : groups) names.push_back(g.name);
  return names;
}

}  // namespace shellflow::mesh
