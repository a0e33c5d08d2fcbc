#pragma once
// The "space mesh" (motion.md; paper section 4.2, eq. 31-35): a coarse mesh of curved
// 20-node tetrahedra filling the fluid domain. Only it is moved (inverse-distance weighting
// of the boundary motion, weights precomputed in the initial configuration); every fluid
// node rides along at parametric coordinates fixed once by `locate`. Per step: one dense
// weight-matrix product over the space-mesh nodes, then 20 multiply-adds per fluid node and
// coordinate. No linear system.
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "shellflow/core/types.h"
#include "shellflow/mesh/mesh.h"

namespace shellflow::motion {

/// Boundary class of a space-mesh node; a node on several boundaries takes the first class
/// in this order.
enum class NodeClass : std::uint8_t { interface, fixed, sliding, interior };

/// Class of every node of a mesh from its boundary groups (interface > fixed > sliding >
/// interior), with up to two unit normals of the sliding planes through each sliding node
/// (zero vectors where unused). Throws InputError naming the mesh, group and node when a
/// group is missing or a sliding group is not planar.
struct NodeClassification {
  std::vector<NodeClass> classes;
  std::vector<std::array<Vec3, 2>> sliding_normals;
};
NodeClassification classify_nodes(const mesh::Mesh& m, const std::vector<std::string>& interface_groups,
                                  const std::vector<std::string>& fixed_groups,
                                  const std::vector<std::string>& sliding_groups);

/// Removes from u its components along the (orthonormal) sliding normals.
inline Vec3 project_on_sliding_planes(Vec3 u, const std::array<Vec3, 2>& normals) {
  for (const Vec3& n : normals) u -= u.dot(n) * n;
  return u;
}

/// How the inverse-distance sums weight their samples.
enum class IdwWeighting {
  plain,  ///< the paper's node sums: a_kj = 1 / d^e
  area,   ///< each sample weighted by the boundary area it represents: a_kj = A_j / d^e
};

struct SpaceMeshOptions {
  std::vector<std::string> interface_groups;  ///< moving wall (the shell's wet surface)
  std::vector<std::string> fixed_groups;      ///< walls, inflow, outflow, far field
  std::vector<std::string> sliding_groups;    ///< symmetry / slip planes (must be planar)
  double interface_exponent = 4.0;            ///< e1
  double fixed_exponent = 4.0;                ///< e2
  IdwWeighting weighting = IdwWeighting::plain;
  /// A fluid node is inside an element when xi_i >= -tol and sum xi <= 1 + tol.
  double location_tolerance = 1e-8;
  /// A fluid node outside every element is attached to the nearest one if its gap is below
  /// this fraction of that element's size; otherwise locate() fails.
  double max_relative_gap = 1e-6;
};

/// Where a fluid node sits in the space mesh: element and the 20 shape-function values.
struct NodeLocation {
  Index element = -1;
  std::array<double, 20> shape{};
};

/// What locate() found.
struct LocationReport {
  Index located = 0;          ///< nodes found inside an element (within the tolerance)
  Index projected = 0;        ///< nodes outside every element, attached to the nearest one
  double max_gap = 0.0;       ///< largest distance between a projected node and its element
  double max_residual = 0.0;  ///< largest |x(xi) - P| over the located nodes
  int max_newton_iterations = 0;
};

class SpaceMesh {
 public:
  /// Classifies the nodes of `space` (20-node tetrahedra, with the fluid mesh's group
  /// names). Throws InputError naming the mesh and group when a group is missing or a
  /// sliding group is not planar, or when the mesh is not cubic or has an inverted element.
  SpaceMesh(const mesh::Mesh& space, SpaceMeshOptions options);

  /// The IDW samples of the interface motion (e.g. the shell's nodes) and of the fixed
  /// boundary (the space mesh's own fixed nodes), weights precomputed and normalised.
  /// `interface_areas` (same length as the samples) is used with IdwWeighting::area.
  void set_interface_samples(std::span<const Vec3> samples, std::span<const double> interface_areas);

  /// Finds every fluid node in the space mesh, once. Throws InputError naming the node when a
  /// node cannot be located within the tolerance.
  LocationReport locate(std::span<const Vec3> fluid_nodes);

  /// Moves the space mesh: interface nodes take `interface_u/v` (one per interface node, in
  /// the order of interface_nodes()), fixed nodes `fixed_u` (empty: zero), interior and
  /// sliding nodes the normalised IDW sums of the sample motion (eq. 33), sliding nodes then
  /// lose the component normal to their plane.
  void move(std::span<const Vec3> interface_u, std::span<const Vec3> interface_v, std::span<const Vec3> sample_u,
            std::span<const Vec3> sample_v, std::span<const Vec3> fixed_u = {});

  /// Sets the motion of every space-mesh node directly (bypassing the IDW), e.g. from
  /// another distribution rule or in tests.
  void set_node_motion(std::span<const Vec3> u, std::span<const Vec3> v);

  /// Fluid node positions and mesh velocities from the space mesh (eq. 31-32, written for
  /// the displacement: x = X + sum_k N_k(xi) u_k, w = sum_k N_k(xi) v_k).
  void interpolate(std::span<Vec3> fluid_x, std::span<Vec3> fluid_w) const;
  /// The fluid nodes' displacements sum_k N_k(xi) u_k alone.
  void interpolate_displacement(std::span<Vec3> fluid_u) const;

  const mesh::Mesh& mesh() const { return mesh_; }
  std::span<const NodeClass> node_classes() const { return classes_; }
  std::span<const Index> interface_nodes() const { return interface_nodes_; }
  std::span<const Index> fixed_nodes() const { return fixed_nodes_; }
  std::span<const NodeLocation> locations() const { return locations_; }
  /// Current displacement and velocity of the space-mesh nodes.
  std::span<const Vec3> displacement() const { return displacement_; }
  std::span<const Vec3> velocity() const { return velocity_; }
  std::vector<Vec3> current_positions() const;
  /// Smallest Jacobian determinant of the cubic map over the elements' nodes and a degree-4
  /// quadrature, divided by the element's straight-sided (vertex) determinant at t = 0:
  /// 1 for an undeformed straight element, <= 0 when an element folds.
  double min_relative_jacobian() const;

 private:
  mesh::Mesh mesh_;
  SpaceMeshOptions options_;
  std::vector<NodeClass> classes_;
  std::vector<Index> interface_nodes_, fixed_nodes_, idw_nodes_;  ///< idw: interior + sliding
  std::vector<std::array<Vec3, 2>> sliding_normals_;              ///< per node (zero vectors if unused)
  std::vector<double> reference_jacobian_;                        ///< per element, straight-sided det J
  std::vector<double> fixed_areas_;                               ///< per fixed node (area weighting)
  // Normalised weights, row per IDW node: samples, then fixed nodes.
  Index num_samples_ = 0;
  std::vector<double> sample_weights_, fixed_weights_;
  std::vector<NodeLocation> locations_;
  std::vector<Vec3> fluid_initial_;  ///< fluid node positions given to locate()
  std::vector<Vec3> displacement_, velocity_;
  mutable std::vector<double> motion_records_;  ///< (u, v) per node, packed for interpolate()
};

/// Lumped boundary area of each node of a block of boundary facets (integral of the node's
/// shape function: positive for 3- and 10-node triangles, zero at the vertices of
/// 6-node ones), indexed like `nodes`.
std::vector<double> lumped_node_areas(std::span<const Vec3> nodes, const mesh::ElementBlock& facets);

}  // namespace shellflow::motion
