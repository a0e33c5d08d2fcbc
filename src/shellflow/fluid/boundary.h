#pragma once
// Boundary conditions on physical groups, imposed strongly on the nodal values after the
// update (fluid.md §9). Priority where groups meet: supersonic inflow > slip wall /
// symmetry > far field > supersonic outflow. Slip-wall and symmetry nodes are constrained
// along every distinct normal of their adjacent faces (clusters more than 30° apart), so
// edges and corners where two walls or a wall and a symmetry plane meet are handled.
#include <array>
#include <functional>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "shellflow/core/types.h"
#include "shellflow/fluid/gas.h"
#include "shellflow/fluid/residual.h"
#include "shellflow/fluid/state.h"
#include "shellflow/mesh/mesh.h"

namespace shellflow::fluid {

enum class BoundaryKind {
  supersonic_inflow,   ///< all five variables from `state`
  supersonic_outflow,  ///< natural (keeps the Taylor–Galerkin boundary term C3)
  slip_wall,           ///< (u - w_wall) . n = 0, pressure kept (paper eq. 29)
  symmetry,            ///< u . n = 0 with the plane's normal
  far_field,           ///< characteristic (Riemann-invariant) state from `state`
};
const char* to_string(BoundaryKind kind);

/// Velocity of a moving slip wall at node `node`, position x, time t.
using WallVelocity = std::function<Vec3(Index node, const Vec3& x, double t)>;

/// Inflow / far-field state varying in space and time.
using StateFunction = std::function<Primitive(const Vec3& x, double t)>;

struct BoundaryCondition {
  std::string group;             ///< physical group (surface) of the mesh
  BoundaryKind kind = BoundaryKind::slip_wall;
  Primitive state;               ///< free stream for inflow and far field
  WallVelocity wall_velocity;    ///< slip wall only; empty: fixed wall
  StateFunction state_at;        ///< replaces `state` when set

  BoundaryCondition() = default;
  BoundaryCondition(std::string group_name, BoundaryKind condition_kind, Primitive constant_state = {},
                    WallVelocity wall = {}, StateFunction varying_state = {})
      : group(std::move(group_name)),
        kind(condition_kind),
        state(constant_state),
        wall_velocity(std::move(wall)),
        state_at(std::move(varying_state)) {}
};

/// The boundary conditions of one mesh: topology at setup, normals at each configuration.
/// Hash of a sorted node triple.
struct FaceKeyHash {
  std::size_t operator()(const std::array<Index, 3>& k) const {
    std::size_t h = std::size_t(k[0]);
    h = h * 1000003u ^ std::size_t(k[1]);
    return h * 1000003u ^ std::size_t(k[2]);
  }
};

class BoundarySet {
 public:
  BoundarySet() = default;
  /// `tets`: the solver's connectivity. Throws InputError for a surface group with no
  /// condition, an unknown group, two conditions on one group, or an inflow state that is
  /// not supersonic.
  BoundarySet(const mesh::Mesh& mesh, std::span<const Index> tets, const IdealGas& gas,
              std::vector<BoundaryCondition> conditions);

  /// Nodal normals and wall constraints on the configuration x.
  void update_normals(std::span<const Vec3> x);

  /// Imposes all conditions on u at time t; x, w: positions and mesh velocity.
  void apply(const IdealGas& gas, double t, std::span<const Vec3> x, std::span<const Vec3> w,
             FluidState& u) const;

  /// Sets the increments of the supersonic-inflow nodes to (imposed state - u_old) at time
  /// t and positions x (for the consistent-mass iterations).
  void impose_inflow_increments(const IdealGas& gas, double t, std::span<const Vec3> x,
                                const FluidState& u_old, FluidState& increment) const;

  /// Faces of natural boundaries (outflow and far field) for the C3 term.
  std::span<const BoundaryFace> natural_faces() const { return natural_faces_; }
  /// Constraint directions at a slip-wall/symmetry node (empty span elsewhere).
  std::span<const Vec3> wall_constraints(Index node) const;
  const std::vector<BoundaryCondition>& conditions() const { return conditions_; }
  /// The boundary face with these nodes (any order), with its owning element. Throws
  /// InputError when it is not a face of a group with a condition.
  BoundaryFace owner_of(Index a, Index b, Index c) const;

 private:
  struct Face {
    BoundaryFace face;
    int condition;
  };
  std::vector<BoundaryCondition> conditions_;
  std::vector<Face> faces_;
  std::unordered_map<std::array<Index, 3>, std::size_t, FaceKeyHash> face_index_;
  std::vector<BoundaryFace> natural_faces_;
  // inflow nodes and their condition
  std::vector<std::pair<Index, int>> inflow_nodes_;
  // slip/symmetry nodes: faces adjacent (CSR, symmetry faces first), constraints, wall condition
  std::vector<Index> wall_nodes_;
  std::vector<Index> wall_face_offsets_;
  std::vector<Index> wall_faces_;
  std::vector<int> wall_moving_condition_;  // condition index with a wall velocity, or -1
  std::vector<std::array<Vec3, 3>> wall_normals_;
  std::vector<int> wall_num_normals_;
  std::vector<Index> wall_slot_;  // node -> index in wall_nodes_, or -1
  // far-field nodes
  std::vector<Index> far_nodes_;
  std::vector<int> far_condition_;
  std::vector<Index> far_face_offsets_;
  std::vector<Index> far_faces_;
  std::vector<Vec3> far_normals_;
};

}  // namespace shellflow::fluid
