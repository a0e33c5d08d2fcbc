#include "shellflow/coupling/interface_maps.h"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <unordered_map>

#include "shellflow/core/error.h"
#include "shellflow/mesh/spatial_index.h"

namespace shellflow::coupling {
namespace {

using FaceKey = std::array<Index, 3>;
struct FaceKeyHash {
  std::size_t operator()(const FaceKey& k) const {
    std::size_t h = std::size_t(k[0]);
    h = h * 1000003u ^ std::size_t(k[1]);
    return h * 1000003u ^ std::size_t(k[2]);
  }
};
FaceKey sorted(FaceKey k) {
  std::sort(k.begin(), k.end());
  return k;
}

const mesh::PhysicalGroup& surface_group(const mesh::Mesh& fluid, std::string_view group) {
  const mesh::PhysicalGroup& g = fluid.group(group);  // throws naming the groups available
  if (g.dim != 2 || g.elements.type != mesh::ElementType::tri3)
    throw_input_error(
        "coupling: group '{}' of mesh '{}' is not a surface of 3-node triangles; "
        "name the fluid's wet boundary (the panel) as coupling.fluid_group",
        g.name, fluid.name);
  return g;
}

}  // namespace

std::vector<WetFace> oriented_wet_faces(const mesh::Mesh& fluid, std::string_view group) {
  const mesh::PhysicalGroup& g = surface_group(fluid, group);
  std::unordered_map<FaceKey, std::size_t, FaceKeyHash> index;
  std::vector<WetFace> faces(static_cast<std::size_t>(g.elements.size()));
  std::vector<char> found(faces.size(), 0);
  for (Index f = 0; f < g.elements.size(); ++f) {
    const auto n = g.elements.element(f);
    faces[std::size_t(f)].nodes = {n[0], n[1], n[2]};
    index.emplace(sorted({n[0], n[1], n[2]}), std::size_t(f));
  }
  static constexpr int tet_faces[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  for (Index e = 0; e < fluid.num_cells(); ++e) {
    const auto t = fluid.cells.element(e);
    for (int opp = 0; opp < 4; ++opp) {
      const auto it = index.find(sorted(
          {t[std::size_t(tet_faces[opp][0])], t[std::size_t(tet_faces[opp][1])], t[std::size_t(tet_faces[opp][2])]}));
      if (it == index.end()) continue;
      auto& face = faces[it->second].nodes;
      const Vec3& a = fluid.nodes[std::size_t(face[0])];
      const Vec3 n = (fluid.nodes[std::size_t(face[1])] - a).cross(fluid.nodes[std::size_t(face[2])] - a);
      if (n.dot(fluid.nodes[std::size_t(t[std::size_t(opp)])] - a) > 0.0) std::swap(face[1], face[2]);
      found[it->second] = 1;
    }
  }
  for (std::size_t f = 0; f < faces.size(); ++f)
    if (!found[f])
      throw_input_error(
          "coupling: triangle ({} {} {}) of group '{}' in mesh '{}' is not a face of "
          "any tetrahedron; regenerate the mesh with the group on the volume's "
          "boundary",
          faces[f].nodes[0], faces[f].nodes[1], faces[f].nodes[2], g.name, fluid.name);
  return faces;
}

WallNodeMap map_wall_nodes(const mesh::Mesh& fluid, std::string_view group, const shell::ShellLocator& locator) {
  const mesh::PhysicalGroup& g = surface_group(fluid, group);
  WallNodeMap map;
  map.group = g.name;
  map.nodes = g.nodes;
  map.points.resize(map.nodes.size());
  map.gaps.resize(map.nodes.size());
  for (std::size_t i = 0; i < map.nodes.size(); ++i) {
    const Vec3& x = fluid.nodes[std::size_t(map.nodes[i])];
    const shell::ClosestPoint c = locator.closest(x);
    map.points[i] = c.point;
    map.gaps[i] = c.distance;
    if (c.distance > map.gap.max_gap || map.gap.worst < 0) {
      const auto node = std::size_t(map.nodes[i]);
      map.gap = {c.distance, map.nodes[i], node < fluid.node_tags.size() ? fluid.node_tags[node] : node + 1, x};
    }
  }
  return map;
}

void snap_wall_nodes(mesh::Mesh& fluid, const WallNodeMap& map, const shell::ShellModel& shell) {
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(shell.num_dofs());
  for (std::size_t i = 0; i < map.nodes.size(); ++i)
    fluid.nodes[std::size_t(map.nodes[i])] = shell::mid_surface_position(shell, map.points[i], zero);
}

LoadPointMap map_load_points(const shell::ShellModel& shell, const mesh::Mesh& fluid, std::string_view group) {
  const std::vector<WetFace> faces = oriented_wet_faces(fluid, group);
  mesh::ElementBlock block;
  block.type = mesh::ElementType::tri3;
  for (const WetFace& f : faces) block.connectivity.insert(block.connectivity.end(), f.nodes.begin(), f.nodes.end());
  const mesh::SurfaceLocator locator(fluid.nodes, block);
  const auto& points = shell.load_points();
  LoadPointMap map;
  map.slots.resize(points.size());
  map.weights.resize(points.size());
  map.sign.resize(points.size());
  map.gaps.resize(points.size());
  std::vector<std::array<Index, 3>> nodes(points.size());
  for (std::size_t k = 0; k < points.size(); ++k) {
    const mesh::SurfacePoint hit = locator.closest(points[k].position);
    const auto& face = faces[std::size_t(hit.element)].nodes;
    nodes[k] = face;
    map.weights[k] = {1.0 - hit.xi.x() - hit.xi.y(), hit.xi.x(), hit.xi.y()};
    const Vec3& a = fluid.nodes[std::size_t(face[0])];
    const Vec3 outward = (fluid.nodes[std::size_t(face[1])] - a).cross(fluid.nodes[std::size_t(face[2])] - a);
    // Into the fluid is -outward.
    map.sign[k] = points[k].normal.dot(-outward) >= 0.0 ? 1.0 : -1.0;
    map.gaps[k] = hit.distance;
    if (hit.distance > map.gap.max_gap || map.gap.worst < 0)
      map.gap = {hit.distance, Index(k), std::size_t(points[k].point.element), points[k].position};
  }
  for (const auto& n : nodes) map.fluid_nodes.insert(map.fluid_nodes.end(), n.begin(), n.end());
  std::sort(map.fluid_nodes.begin(), map.fluid_nodes.end());
  map.fluid_nodes.erase(std::unique(map.fluid_nodes.begin(), map.fluid_nodes.end()), map.fluid_nodes.end());
  for (std::size_t k = 0; k < points.size(); ++k)
    for (int i = 0; i < 3; ++i)
      map.slots[k][std::size_t(i)] =
          Index(std::lower_bound(map.fluid_nodes.begin(), map.fluid_nodes.end(), nodes[k][std::size_t(i)]) -
                map.fluid_nodes.begin());
  return map;
}

void check_gap(const GapReport& gap, double max_gap, std::string_view what) {
  if (gap.max_gap <= max_gap) return;
  const bool wall = what.starts_with("fluid");
  throw_input_error(
      "{}: the largest gap is {:.3e} m at {} {} ({} {}) at ({:.6g}, {:.6g}, {:.6g}) m, "
      "above coupling.max_gap = {:.3e} m: the shell and fluid meshes do not describe "
      "the same wet surface; check the geometry and coupling.fluid_group, or raise max_gap",
      what, gap.max_gap, wall ? "fluid node" : "shell load point", gap.worst,
      wall ? "Gmsh node tag" : "in shell element", gap.tag, gap.where.x(), gap.where.y(), gap.where.z(), max_gap);
}

void transfer_to_load_points(const LoadPointMap& map, std::span<const double> values, std::span<double> out) {
  for (std::size_t k = 0; k < map.slots.size(); ++k) {
    const auto& s = map.slots[k];
    const auto& w = map.weights[k];
    out[k] = w[0] * values[std::size_t(s[0])] + w[1] * values[std::size_t(s[1])] + w[2] * values[std::size_t(s[2])];
  }
}

}  // namespace shellflow::coupling
