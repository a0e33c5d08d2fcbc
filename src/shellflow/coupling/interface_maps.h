#pragma once
// Interface maps between the shell mid-surface and the fluid's wet boundary (coupling.md,
// "Interface maps"): built once before the run, used at every exchange.
//
//   fluid wet node i   -> closest shell point P_s(i) = (element, xi1, xi2); the fluid node is
//                         then moved onto it (snap_wall_nodes), before the flow and the mesh
//                         mover are built, so that the wall follows the shell exactly;
//   shell load point k -> closest point P_f(k) on the fluid wet triangles: three fluid nodes
//                         with barycentric weights, and the orientation sign that makes
//                         sign_k * N_k (N_k the shell normal, oriented like the directors V)
//                         point into the fluid.
// Candidates come from spatial indices (AABB trees): no quadratic search.
#include <array>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "shellflow/core/types.h"
#include "shellflow/mesh/mesh.h"
#include "shellflow/shell/shell_model.h"
#include "shellflow/shell/shell_queries.h"

namespace shellflow::coupling {

/// The largest gap of a map and where it occurs.
struct GapReport {
  double max_gap = 0.0;
  Index worst = -1;     ///< fluid node (wall map) or shell load point (load map)
  std::size_t tag = 0;  ///< Gmsh tag of that fluid node (wall map), shell element (load map)
  Vec3 where = Vec3::Zero();
};

/// Fluid wet-boundary nodes -> closest points of the shell mid-surface.
struct WallNodeMap {
  std::string group;                      ///< fluid wet group
  std::vector<Index> nodes;               ///< fluid nodes of the group (sorted, as in the mesh group)
  std::vector<shell::ShellPoint> points;  ///< closest shell point of each node
  std::vector<double> gaps;               ///< distance node -> shell point before snapping
  GapReport gap;
};

/// Shell load points -> fluid wet triangles.
struct LoadPointMap {
  std::vector<Index> fluid_nodes;              ///< the fluid nodes the map reads (sorted, unique)
  std::vector<std::array<Index, 3>> slots;     ///< per load point: its triangle's vertices as
                                               ///< positions in fluid_nodes
  std::vector<std::array<double, 3>> weights;  ///< barycentric weights (sum 1)
  std::vector<double> sign;                    ///< +1 when the shell normal (like V) points into the fluid, else -1
  std::vector<double> gaps;
  GapReport gap;
};

/// One wet triangle of the fluid mesh with its outward orientation (out of the fluid, into
/// the structure): `nodes` ordered so that (b - a) x (c - a) points out of the fluid.
struct WetFace {
  std::array<Index, 3> nodes;
};

/// The triangles of a fluid boundary group, oriented out of the fluid (from the tetrahedron
/// that owns each). Throws InputError for a group that is not a surface of tet faces.
std::vector<WetFace> oriented_wet_faces(const mesh::Mesh& fluid, std::string_view group);

/// Maps every node of the fluid group `group` to its closest shell point.
WallNodeMap map_wall_nodes(const mesh::Mesh& fluid, std::string_view group, const shell::ShellLocator& locator);

/// Moves every mapped fluid node exactly onto its shell point (undeformed shell).
void snap_wall_nodes(mesh::Mesh& fluid, const WallNodeMap& map, const shell::ShellModel& shell);

/// Maps every shell load point to the closest point of the fluid group's triangles.
LoadPointMap map_load_points(const shell::ShellModel& shell, const mesh::Mesh& fluid, std::string_view group);

/// Throws InputError when `gap` exceeds max_gap: names the map, the worst entity, its gap
/// and the fix.
void check_gap(const GapReport& gap, double max_gap, std::string_view what);

/// Value at every load point of a fluid field given at map.fluid_nodes (e.g. p):
/// out_k = sum_i w_ki f(slot_ki).
void transfer_to_load_points(const LoadPointMap& map, std::span<const double> values_at_nodes, std::span<double> out);

}  // namespace shellflow::coupling
