#pragma once
// Boundary conditions on physical groups, imposed strongly on the nodal values after the
// update (fluid.md §9). Priority where groups meet: supersonic inflow > no-slip wall >
// slip wall / symmetry > far field > supersonic outflow. Slip-wall and symmetry nodes are constrained
// along every distinct normal of their adjacent faces (clusters more than 30° apart), so
// edges and corners where two walls or a wall and a symmetry plane meet are handled.
// Exception (one-layer slabs, where every node lies on a symmetry plane): a slip-wall or
// symmetry node that also lies on a far-field face first gets the far-field state, then
// its wall constraints (the walls win for their normal components, the far field gives
// the rest; rho E recomputed from the far-field pressure).
// Wall velocities: along a symmetry normal u . n = 0 always; along the (Gram–Schmidt
// orthogonalised) slip-wall normals (u - v_wall) . n = 0, v_wall from the node's slip-wall
// group (set per node with set_wall_velocity, else its closure; the last such group in
// the condition list when several meet).
#include <array>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
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
  no_slip_wall,        ///< u = u_wall (viscous runs only); adiabatic, or T = wall_temperature
};
const char* to_string(BoundaryKind kind);

/// Velocity of a moving wall at node `node`, position x, time t.
using WallVelocity = std::function<Vec3(Index node, const Vec3& x, double t)>;

/// Inflow / far-field state varying in space and time.
using StateFunction = std::function<Primitive(const Vec3& x, double t)>;

struct BoundaryCondition {
  std::string group;  ///< physical group (surface) of the mesh
  BoundaryKind kind = BoundaryKind::slip_wall;
  Primitive state;             ///< free stream for inflow and far field
  WallVelocity wall_velocity;  ///< slip and no-slip walls; empty: fixed wall
  StateFunction state_at;      ///< replaces `state` when set
  /// No-slip wall only: imposed wall temperature (K); empty: adiabatic (no heat flux).
  std::optional<double> wall_temperature;

  BoundaryCondition() = default;
  BoundaryCondition(std::string group_name, BoundaryKind condition_kind, Primitive constant_state = {},
                    WallVelocity wall = {}, StateFunction varying_state = {})
      : group(std::move(group_name)),
        kind(condition_kind),
        state(constant_state),
        wall_velocity(std::move(wall)),
        state_at(std::move(varying_state)) {}

  /// A no-slip wall moving with `wall` (empty: fixed), adiabatic unless `temperature` is set.
  static BoundaryCondition no_slip(std::string group_name, WallVelocity wall = {},
                                   std::optional<double> temperature = {}) {
    BoundaryCondition bc(std::move(group_name), BoundaryKind::no_slip_wall, {}, std::move(wall));
    bc.wall_temperature = temperature;
    return bc;
  }
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
  /// condition, an unknown group, two conditions on one group, an inflow state that is
  /// not supersonic, a no-slip wall with an inviscid gas, or a wall temperature <= 0.
  BoundarySet(const mesh::Mesh& mesh, std::span<const Index> tets, const IdealGas& gas,
              std::vector<BoundaryCondition> conditions);

  /// Nodal normals and wall constraints on the configuration x. The first call also takes
  /// x as the reference: the faces of a group that lie in one plane there (a facet) keep
  /// their normals while the facet's nodes stay in that plane, and a node whose faces all
  /// lie in such facets keeps its normals (symmetry planes along which the mesh slides, a
  /// flat wall: no work per step).
  void update_normals(std::span<const Vec3> x);
  /// Nodes whose normals the last update_normals computed (the rest were kept).
  Index normals_updated() const { return normals_updated_; }

  /// Per-node wall velocities of the slip_wall or no_slip_wall group `group`, one per node
  /// of mesh.group(group).nodes in that (sorted) order. They replace the group's closure
  /// `wall_velocity` until set again. Throws InputError for another kind, a group with no
  /// condition, or a size mismatch.
  void set_wall_velocity(std::string_view group, std::span<const Vec3> velocity);
  /// The per-node velocities set for condition `c` (empty: not set), for snapshots.
  const std::vector<std::vector<Vec3>>& set_wall_velocities() const { return set_velocity_; }
  /// Restores what set_wall_velocities() returned (same boundary set).
  void restore_wall_velocities(const std::vector<std::vector<Vec3>>& v);

  /// Imposes all conditions on u at time t; x, w: positions and mesh velocity.
  /// `initial_state`: u is a given initial field, not the result of a step (adiabatic
  /// no-slip walls then keep the pressure instead of the updated total energy).
  void apply(const IdealGas& gas, double t, std::span<const Vec3> x, std::span<const Vec3> w, FluidState& u,
             bool initial_state = false) const;

  /// Sets the increments of the Dirichlet values at time t and positions x (for the
  /// consistent-mass iterations): supersonic-inflow nodes to (imposed state - u_old);
  /// no-slip nodes' momentum to (rho_old + d rho) u_wall - m_old, and their energy too when
  /// the wall is isothermal.
  void impose_dirichlet_increments(const IdealGas& gas, double t, std::span<const Vec3> x, const FluidState& u_old,
                                   FluidState& increment) const;

  /// Projects the increments of the slip-wall and symmetry nodes so that u_old + increment
  /// meets their wall constraints (the projection of apply, pressure kept), for the
  /// consistent-mass iterations: without it the unconstrained normal momentum of those nodes
  /// spreads to their neighbours through the consistent mass during the sweeps.
  void impose_wall_increments(const IdealGas& gas, double t, std::span<const Vec3> x, const FluidState& u_old,
                              FluidState& increment) const;

  /// Weak slip walls (docs/fluid.md "Slip walls"): adds to r the change of the Galerkin
  /// residual when the gas's normal flux through the slip-wall faces, F(U) . n, is replaced by
  /// the wall's, F(U*) . n with U* = U less its normal velocity relative to the wall (pressure
  /// kept): r_a += dt * integral of N_a (F(U) - F(U*)) . n over the faces (exact for linear
  /// fluxes: consistent surface quadrature). With it, apply() leaves the slip-wall normals to the
  /// flux and imposes only the symmetry planes'.
  void add_weak_wall_flux(const IdealGas& gas, double t, double dt, std::span<const Vec3> x, const FluidState& u,
                          FluidState& r) const;
  bool weak_walls() const { return weak_walls_; }
  void set_weak_walls(bool weak) { weak_walls_ = weak; }

  /// Faces of natural boundaries (outflow and far field) for the C3 term.
  std::span<const BoundaryFace> natural_faces() const { return natural_faces_; }
  /// Faces of adiabatic no-slip walls (they carry the work of the viscous stress).
  std::span<const BoundaryFace> adiabatic_wall_faces() const { return adiabatic_wall_faces_; }
  /// Nodes where the far-field state is imposed (sorted), including slab nodes that also
  /// get wall/symmetry constraints afterwards.
  std::span<const Index> far_field_nodes() const { return far_nodes_; }
  /// Constraint directions at a slip-wall/symmetry node (empty span elsewhere), orthonormal,
  /// the symmetry-plane directions first.
  std::span<const Vec3> wall_constraints(Index node) const;
  /// How many of wall_constraints(node) come from symmetry planes (u . n = 0 there).
  int symmetry_constraints(Index node) const;
  const std::vector<BoundaryCondition>& conditions() const { return conditions_; }
  /// The boundary face with these nodes (any order), with its owning element. Throws
  /// InputError when it is not a face of a group with a condition.
  BoundaryFace owner_of(Index a, Index b, Index c) const;

 private:
  struct Face {
    BoundaryFace face;
    int condition;
  };
  /// A node's position in the node list of a condition's group.
  struct GroupSlot {
    int condition;
    Index index;
  };
  Vec3 slip_velocity(std::size_t s, Index a, const Vec3& x, double t) const;
  Vec3 no_slip_velocity(std::size_t s, Index a, const Vec3& x, double t) const;
  void apply_far_field(const IdealGas& gas, double t, std::span<const Vec3> x, std::span<const Vec3> w, std::size_t s,
                       FluidState& u) const;
  /// q with the wall constraints of wall node s imposed (pressure kept).
  Conservative wall_projection(const IdealGas& gas, double t, std::span<const Vec3> x, std::size_t s,
                               Conservative q) const;
  /// f(slot, node) for every slip-wall/symmetry node, on the pool's threads unless a slip wall
  /// takes its velocity from a closure (then serially).
  template <class F>
  void for_each_wall_node(const F& f) const;
  std::vector<BoundaryCondition> conditions_;
  std::vector<Face> faces_;
  std::unordered_map<std::array<Index, 3>, std::size_t, FaceKeyHash> face_index_;
  std::vector<BoundaryFace> natural_faces_;
  std::vector<BoundaryFace> slip_wall_faces_;
  bool weak_walls_ = false;
  std::vector<BoundaryFace> adiabatic_wall_faces_;
  // no-slip nodes and their condition
  std::vector<Index> no_slip_nodes_;
  std::vector<int> no_slip_condition_;
  std::vector<Index> no_slip_index_;  // position in the group's node list
  // per-node wall velocities set from outside, per condition (empty: not set)
  std::vector<std::vector<Vec3>> set_velocity_;
  std::vector<Index> group_size_;  // nodes per condition's group
  // inflow nodes and their condition
  std::vector<std::pair<Index, int>> inflow_nodes_;
  // slip/symmetry nodes: faces adjacent (CSR, symmetry faces first), constraints, wall condition
  std::vector<Index> wall_nodes_;
  std::vector<Index> wall_face_offsets_;
  std::vector<Index> wall_faces_;
  std::vector<Index> wall_sym_faces_;     // leading symmetry faces per node
  std::vector<Index> wall_slip_offsets_;  // CSR: adjacent slip-wall groups, ascending
  std::vector<GroupSlot> wall_slip_groups_;
  std::vector<std::array<Vec3, 3>> wall_normals_;
  std::vector<int> wall_num_normals_;
  std::vector<int> wall_num_sym_normals_;
  // Planar facets (update_normals): the faces of a condition's group split by the plane
  // they lie in at the reference configuration (up to 62 facets in all; faces beyond, and
  // faces of curved groups, belong to none), each facet's nodes, the facet of every face
  // (-1: none) and per wall/far-field node its faces' facets as bits (bit 63: a face of
  // no facet: always recomputed).
  struct Facet {
    Vec3 normal = Vec3::Zero();
    double offset = 0.0, tolerance = 0.0;
    std::vector<Index> nodes;
  };
  void set_reference_facets(std::span<const Vec3> x);
  std::uint64_t facets_off_their_planes(std::span<const Vec3> x) const;
  void update_wall_node(std::size_t s, std::span<const Vec3> x);
  void update_far_node(std::size_t s, std::span<const Vec3> x);
  void restore_reference_node(std::size_t s, bool wall);
  std::vector<Facet> facets_;
  std::vector<std::uint64_t> wall_facets_, far_facets_;
  // The normals at the reference (a node whose facets come back into their planes gets them
  // back) and the facets that were off their planes at the last update.
  std::vector<std::array<Vec3, 3>> reference_wall_normals_;
  std::vector<int> reference_wall_num_normals_, reference_wall_num_sym_normals_;
  std::vector<Vec3> reference_far_normals_;
  std::uint64_t last_off_ = 0;
  bool have_reference_ = false;
  Index normals_updated_ = 0;
  std::vector<Index> wall_slot_;  // node -> index in wall_nodes_, or -1
  // far-field nodes
  std::vector<Index> far_nodes_;
  std::vector<int> far_condition_;
  std::vector<Index> far_face_offsets_;
  std::vector<Index> far_faces_;
  std::vector<Vec3> far_normals_;
};

}  // namespace shellflow::fluid
