#pragma once
// A shell model: mesh + section + supports + loads (dead, follower, and per-load-point loads
// set from outside), and the global operators of the positional shell (internal force,
// tangent, mass) assembled into Eigen sparse matrices whose pattern is computed once.
// Definitions: shell_model.cpp (construction, assembly), shell_supports.cpp, shell_loads.cpp. Unknowns: increments u =
// y - y0, node-major, 7 per node [dx (3), dG (3), a] (shell.md §0, §2.5).
#include <Eigen/Sparse>
#include <array>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "shellflow/core/time_function.h"
#include "shellflow/fem/shape_functions.h"
#include "shellflow/mesh/mesh.h"
#include "shellflow/shell/material.h"
#include "shellflow/shell/shell_element.h"
#include "shellflow/shell/shell_point.h"

namespace shellflow::shell {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

struct ShellSection {
  double thickness = 0.0;
  SvkMaterial material;
  int plane_degree = 6;      ///< in-plane quadrature degree (shell.md §5: 6, 12 points)
  int thickness_points = 3;  ///< Gauss points through the thickness (3; 5 for checks)
};

/// Components of the nodal position and director that a support fixes, in global axes, on
/// every node of a physical group (shell.md §10). Fixed components keep their initial
/// value (zero increment).
struct Support {
  std::string group;
  std::array<bool, 3> fix_position{};
  std::array<bool, 3> fix_director{};
  bool fix_thickness_parameter = false;

  /// Position fixed at X, director fixed at V ([decision] of §10: all of G).
  static Support clamped(std::string group);
  /// Soft simple support: position fixed, director free.
  static Support simply_supported(std::string group);
  /// Symmetry plane with unit normal along global axis `normal_axis` (0, 1, 2):
  /// x·n = X·n and G·n = 0.
  static Support symmetry_plane(std::string group, int normal_axis);
  /// Roller: only the position component along `free_axis` is free; the director is fixed
  /// (clamped-sliding) or free.
  static Support sliding(std::string group, int free_axis, bool clamp_director);
};

/// A support along arbitrary unit directions (shell.md §10): the increments of the nodal
/// position along `position_directions` and of the director along `director_directions`
/// are zero on every node of the group. Directions that are not global axes are handled by
/// a local orthonormal basis T per node (the model's to_local / to_global).
struct DirectionalSupport {
  std::string group;
  std::vector<Vec3> position_directions;
  std::vector<Vec3> director_directions;

  /// Symmetry plane with unit normal n (any direction): x·n = X·n and G·n = 0.
  static DirectionalSupport symmetry_plane(std::string group, const Vec3& normal);
  /// Roller along d: the position moves only along d; the director is fixed
  /// (clamped-sliding) or free.
  static DirectionalSupport roller(std::string group, const Vec3& direction, bool clamp_director);
};

/// Prescribed motion of a group (shell.md §10): x(t) = X + f(t) d, and, when `rotation_axis`
/// is not zero, G(t) = R(g(t)) V with R the rotation by the angle g(t) (radians) about
/// `rotation_axis` (directors are free vectors: only the axis direction matters). The
/// position (and director) of the group's nodes become fixed dofs whose values the solver
/// sets with ShellModel::apply_prescribed before each step.
struct PrescribedMotion {
  std::string group;
  Vec3 displacement = Vec3::Zero();                                 ///< d
  TimeFunction displacement_history = TimeFunction::constant(1.0);  ///< f(t)
  Vec3 rotation_axis = Vec3::Zero();                                ///< zero: the director is left free
  TimeFunction rotation_angle = TimeFunction::constant(0.0);        ///< g(t)
};

/// Dead traction per reference area on a surface group of the shell mesh (empty: the whole
/// shell), F_x^j = ∫ φ_j t dA0 (shell.md §11).
struct SurfaceTraction {
  std::string group;
  Vec3 traction = Vec3::Zero();
};

/// Dead line load per reference length on the edges of a physical group of lines.
struct LineLoad {
  std::string group;
  Vec3 force_per_length = Vec3::Zero();
};

/// Dead point force on a node.
struct PointLoad {
  Index node = 0;
  Vec3 force = Vec3::Zero();
};

/// Conservative edge couple per reference length about the unit edge tangent `axis`
/// (shell.md §11), acting on the directors of a group's nodes. Positive about +axis.
struct EdgeCouple {
  std::string group;
  Vec3 axis = Vec3::UnitY();
  double moment_per_length = 0.0;
};

/// Follower pressure on the mid-surface (shell.md §11), positive along the current normal
/// oriented like the directors V; per current area. `group` names a surface group of the
/// shell mesh, or is empty for the whole shell. Makes the tangent non-symmetric.
/// Without `history` the pressure is `pressure` times the analysis load factor; with it,
/// `pressure * history(t)` at the solver's evaluation time t (NewmarkSolver: the end of the
/// step for Newmark, its midpoint for the midpoint rule, the current time in
/// set_initial_state; StaticSolver: the load factor as pseudo-time), whatever the load
/// factor (e.g. a cavity pressure).
struct FollowerPressure {
  std::string group;
  double pressure = 0.0;
  std::optional<TimeFunction> history = std::nullopt;
};

/// An in-plane quadrature point of the shell (section.plane_degree rule), where the
/// follower-pressure kernel and the point loads act (ShellModel::load_points).
struct LoadPoint {
  ShellPoint point{};            ///< element and xi of the quadrature point
  Vec3 position = Vec3::Zero();  ///< reference mid-surface point X̂(xi)
  Vec3 normal = Vec3::Zero();    ///< reference unit normal X̂_1 × X̂_2 / |…| (oriented like V)
  double weight = 0.0;           ///< reference area weight w_q |X̂_1 × X̂_2|
};

/// Elements of one triangle type with their precomputed geometry and a colouring in which
/// no two elements of a colour share a node (race-free parallel assembly).
template <class Tri>
struct ElementSet {
  ShellQuadrature<Tri> rule;
  std::vector<ShellElementGeometry<Tri>> geometry;
};

class ShellModel {
 public:
  /// Builds directors (shell.md §9), element geometry and the matrix pattern. Throws
  /// InputError for a non-triangle mesh, a non-positive thickness, a kink or inconsistent
  /// orientation at a node, or J0 <= 0 in an element (each naming the node / element).
  ShellModel(mesh::Mesh mesh, const ShellSection& section);

  const mesh::Mesh& mesh() const { return mesh_; }
  const ShellSection& section() const { return section_; }
  Index num_nodes() const { return mesh_.num_nodes(); }
  Index num_dofs() const { return dofs_per_node * mesh_.num_nodes(); }
  /// Initial unit directors V (nodal normals of the mid-surface).
  const std::vector<Vec3>& directors() const { return directors_; }
  /// Bounding-box diagonal of the mid-surface (length scale of the convergence test).
  double reference_length() const { return reference_length_; }

  /// Axis-aligned support (components in global axes). Throws InputError naming the
  /// group, the mesh and the groups available when the group is missing.
  void add_support(const Support& support);
  /// Support along arbitrary directions; throws InputError for a zero or non-finite
  /// direction.
  void add_support(const DirectionalSupport& support);
  /// Hard simple support on a group of lines: position fixed and G·t = 0 along the edge
  /// tangent t at each node (at a corner of the group, along both tangents).
  void add_hard_simple_support(const std::string& group);
  /// Prescribed motion of a group; see PrescribedMotion.
  void add_prescribed_motion(const PrescribedMotion& motion);
  /// Writes the prescribed increments at time t into u (x rows: f(t) d; G rows:
  /// R(g(t)) V − V), leaving every other dof as it is. No-op without prescribed motions.
  void apply_prescribed(double t, Eigen::VectorXd& u) const;
  /// Writes the prescribed rates at time t into v (x rows: f'(t) d; G rows:
  /// g'(t) axis × R(g(t)) V), leaving every other dof as it is.
  void apply_prescribed_velocity(double t, Eigen::VectorXd& v) const;
  bool has_prescribed_motion() const { return !prescribed_.empty(); }
  void add_surface_traction(const SurfaceTraction& traction);
  void add_line_load(const LineLoad& load);
  void add_point_load(const PointLoad& load);
  void add_edge_couple(const EdgeCouple& couple);
  void add_follower_pressure(const FollowerPressure& pressure);
  /// Dead body force per unit mass (gravity), shell.md §6: F = M b with b on the x rows
  /// (Σ φ_k = 1 makes this ∫ρ φ_j b dV0 on x and ∫ρ φ_j (h/2) ξ3 b dV0 on G).
  void add_gravity(const Vec3& acceleration);

  /// Per dof: 1 when a support fixes it. For a node with a local basis (has_local_frames),
  /// the flags of its position / director rows refer to the local components.
  const std::vector<char>& constrained() const { return constrained_; }

  /// Local bases of supports along non-axis directions (shell.md §10). A solver that
  /// supports them brings the Newton system to local components before applying
  /// constrained() and the correction back after solving:
  ///   model.to_local(K); model.to_local(rhs);  solve;  model.to_global(du);
  /// (K: Tᵀ K T, in place on a matrix with the pattern of make_matrix; vectors: Tᵀ v;
  /// to_global: T v). All three are no-ops when no node has a rotated basis.
  bool has_local_frames() const { return !frames_.empty(); }
  void to_local(SparseMatrix& K) const;
  void to_local(Eigen::VectorXd& v) const;
  void to_global(Eigen::VectorXd& v) const;
  /// Euclidean norms of the free part and of the fixed part (the directions the supports
  /// fix) of a vector in global components, e.g. a residual and its reactions. Right with
  /// or without local frames.
  double free_norm(const Eigen::VectorXd& v) const;
  double fixed_norm(const Eigen::VectorXd& v) const;
  /// Removes the fixed part of v (global components), leaving the free part.
  void remove_fixed_part(Eigen::VectorXd& v) const;
  /// Dead external force at load factor 1.
  const Eigen::VectorXd& reference_load() const { return reference_load_; }
  /// Adds the state- and time-dependent loads to `force`: edge couples and follower
  /// pressures without history at load factor `load_factor`, follower pressures with a
  /// history at time `time`, and the point pressures and point tractions as set (not
  /// scaled). When K is given (made by make_matrix) subtracts their load stiffness from it
  /// (K is the tangent of F_int - F_ext), scattered in the coloured element loop.
  void add_follower_loads(const Eigen::VectorXd& u, double load_factor, double time, Eigen::VectorXd& force,
                          SparseMatrix* K) const;
  /// Adds ∂/∂λ of add_follower_loads(u, λ, λ, ...) at λ = load_factor (statics, where the
  /// load factor is also the time of the histories): edge couples and pressures without
  /// history at factor 1, pressures with history times history'(λ); no point loads.
  void add_follower_load_direction(const Eigen::VectorXd& u, double load_factor, Eigen::VectorXd& direction) const;
  bool has_follower_loads() const {
    return !edge_couples_.empty() || !pressures_.empty() || !point_pressure_.empty() || !point_traction_.empty();
  }
  /// False with follower pressure or point pressures (their load stiffness is not
  /// symmetric): the solvers then factorise with LU.
  bool symmetric_tangent() const { return pressures_.empty() && point_pressure_.empty(); }

  /// The in-plane quadrature points of every element, element-major (element 0's points in
  /// rule order first), where follower pressures and point loads act; their weights sum to
  /// the reference area.
  const std::vector<LoadPoint>& load_points() const { return load_points_; }
  /// Follower pressure per load point (per current area, positive along the current normal
  /// oriented like V, with load stiffness, like FollowerPressure), not scaled by the load
  /// factor. One value per load point (InputError otherwise). Kept until changed: every
  /// later add_follower_loads (every Newton iteration of a solver) reads these values.
  void set_point_pressure(std::span<const double> pressure);
  /// Dead traction per reference area at each load point (F_x^j += φ_j t_q weight_q), not
  /// scaled by the load factor; one vector per load point (InputError otherwise).
  void set_point_traction(std::span<const Vec3> traction);
  /// Removes the point pressures and point tractions.
  void clear_point_loads();

  /// A matrix with the model's sparsity pattern (all node pairs of an element, 7x7 blocks).
  SparseMatrix make_matrix() const;
  /// Internal force at u and, when K is given (made by make_matrix), the tangent. Returns
  /// false when det A <= 0 at some point (the state is not admissible).
  bool assemble(const Eigen::VectorXd& u, Eigen::VectorXd& f_int, SparseMatrix* K) const;
  double strain_energy(const Eigen::VectorXd& u) const;
  /// Constant consistent mass (a made by make_matrix).
  void assemble_mass(SparseMatrix& M) const;

  /// Mean displacement of the nodes of a group at u.
  Vec3 mean_displacement(const std::string& group, const Eigen::VectorXd& u) const;

 private:
  template <class Tri>
  void build(ElementSet<Tri>& set);
  template <class F>
  void for_each_element_parallel(F&& f) const;
  /// Cells of a surface group, or every cell when `group` is empty (loads on the whole
  /// shell); InputError naming `load_name` for a group that is not a surface.
  std::vector<Index> surface_cells(const std::string& group, std::string_view load_name) const;
  void compute_directors();
  void compute_pattern();
  void compute_load_points();
  /// Follower pressures (scale per entry of pressures_, plus the point pressures when
  /// `with_point_pressure`) with their load stiffness.
  void add_pressure_loads(const Eigen::VectorXd& u, const std::vector<double>& scale, bool with_point_pressure,
                          Eigen::VectorXd& force, SparseMatrix* K) const;
  /// Edge couples at factor `factor` with their load stiffness.
  void add_edge_couples(const Eigen::VectorXd& u, double factor, Eigen::VectorXd& force, SparseMatrix* K) const;
  /// Throws SolverError unless K has the pattern of make_matrix.
  void check_pattern(const SparseMatrix& K, std::string_view what) const;
  void scatter(Index e, const double* Ke, int nd, SparseMatrix& K) const;

  mesh::Mesh mesh_;
  ShellSection section_;
  std::vector<Vec3> directors_;
  double reference_length_ = 0.0;
  std::variant<ElementSet<fem::Tri3>, ElementSet<fem::Tri6>, ElementSet<fem::Tri10>> elements_;
  std::vector<std::vector<Index>> colors_;
  SparseMatrix pattern_;
  /// offsets_[(e * n + b) * n * 7 + c * n + a]: index in the value array of row 7*node_a
  /// of column 7*node_b + c (rows of a node are 7 consecutive entries).
  std::vector<int> offsets_;
  std::vector<char> constrained_;
  /// Fixes the increment of 3-vector `part` (0: position, 1: director) of a node along
  /// the unit direction d (ignored when already fixed) and updates the node's basis.
  void fix_direction(Index node, int part, const Vec3& d);
  /// Per (node, part): projector on the fixed directions.
  std::vector<Mat3> fixed_projector_;
  /// Rotated 3-vectors: (first dof, T with the fixed directions first).
  std::vector<std::pair<Index, Mat3>> frames_;
  /// Per (node, part): index in frames_, or -1 (global axes).
  std::vector<int> frame_index_;
  std::vector<PrescribedMotion> prescribed_;
  /// Per prescribed motion: its nodes.
  std::vector<std::vector<Index>> prescribed_nodes_;
  Eigen::VectorXd reference_load_;
  std::vector<EdgeCouple> edge_couples_;
  /// Per edge couple: nodes and their nodal couple weights m_j / m = ∫ phi_j ds0.
  std::vector<std::vector<std::pair<Index, double>>> edge_couple_weights_;
  /// Per edge couple and node: value-array index of row 7 n + 3 in columns 7 n + 3, +4, +5.
  std::vector<std::vector<std::array<int, 3>>> edge_couple_offsets_;
  struct PressureLoad {
    double pressure = 0.0;
    std::optional<TimeFunction> history = std::nullopt;
    std::vector<Index> cells{};
  };
  std::vector<PressureLoad> pressures_;
  std::vector<LoadPoint> load_points_;
  int points_per_element_ = 0;
  std::vector<double> point_pressure_;  ///< empty or one per load point
  std::vector<Vec3> point_traction_;    ///< empty or one per load point
  Eigen::VectorXd point_traction_force_;
};

/// Nodal values of a 7-per-node vector.
inline Vec3 node_position_increment(const Eigen::VectorXd& u, Index n) { return u.segment<3>(dofs_per_node * n); }
inline Vec3 node_director_increment(const Eigen::VectorXd& u, Index n) { return u.segment<3>(dofs_per_node * n + 3); }

}  // namespace shellflow::shell
