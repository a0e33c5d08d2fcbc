#pragma once
// Mesh containers: one cell block of a single Gmsh element type, nodes, and named
// physical groups of boundary (or lower-dimensional) entities.
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "shellflow/core/types.h"

namespace shellflow::mesh {

/// Element types by Gmsh number (`.msh` 4.1). Only the ones shellflow uses.
enum class ElementType : int {
  line2 = 1,
  tri3 = 2,
  tet4 = 4,
  line3 = 8,
  tri6 = 9,
  tet10 = 11,
  point = 15,
  tri10 = 21,
  line4 = 26,
  tet20 = 29,
};

/// Facts about an element type: dimension, order, number of nodes (vertices first).
struct ElementInfo {
  ElementType type;
  int dim;
  int order;
  int num_nodes;
  int num_vertices;
  const char* short_name;  ///< "tet20", "tri10", ... (used in JSON and messages)
  const char* name;        ///< "20-node tetrahedron"
};
/// Throws InputError for a type shellflow does not handle.
const ElementInfo& element_info(ElementType type);
const ElementInfo& element_info(int gmsh_type);
bool is_supported_element_type(int gmsh_type);
/// Lower-dimensional element type of the same order: tet20 -> tri10 -> line4.
ElementType facet_type(ElementType type);

/// Elements of one type, flat connectivity (0-based node indices, Gmsh node order).
struct ElementBlock {
  ElementType type = ElementType::tri3;
  std::vector<Index> connectivity;

  int nodes_per_element() const { return element_info(type).num_nodes; }
  Index size() const { return static_cast<Index>(connectivity.size()) / nodes_per_element(); }
  std::span<const Index> element(Index e) const {
    const auto n = static_cast<std::size_t>(nodes_per_element());
    return {connectivity.data() + static_cast<std::size_t>(e) * n, n};
  }
};

/// A named physical group. `elements` holds the group's elements (boundary facets for a
/// boundary group; for a group of the mesh's own dimension, `cells` lists cell indices).
struct PhysicalGroup {
  std::string name;
  int dim = 0;
  int tag = 0;
  ElementBlock elements;     ///< elements of dimension `dim` (empty for dim 0)
  std::vector<Index> nodes;  ///< sorted unique node indices of the group
  std::vector<Index> cells;  ///< cell indices, when `dim` equals the mesh dimension
};

/// A mesh of one element type, with its nodes and physical groups.
struct Mesh {
  std::string name;                    ///< e.g. "fluid", "space", "shell"
  std::string source;                  ///< file it came from (for messages)
  std::vector<Vec3> nodes;             ///< node coordinates
  std::vector<std::size_t> node_tags;  ///< Gmsh tag of each node (for messages and .msh output)
  ElementBlock cells;                  ///< the mesh's cells (highest dimension)
  std::vector<PhysicalGroup> groups;

  Index num_nodes() const { return static_cast<Index>(nodes.size()); }
  Index num_cells() const { return cells.size(); }
  int dim() const { return element_info(cells.type).dim; }
  /// nullptr when absent.
  const PhysicalGroup* find_group(std::string_view group_name) const;
  /// Throws InputError naming the mesh, the group and the groups available.
  const PhysicalGroup& group(std::string_view group_name) const;
  std::vector<std::string> group_names() const;
};

}  // namespace shellflow::mesh
