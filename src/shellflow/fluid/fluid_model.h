#pragma once
// FluidModel: compressible Euler or Navier–Stokes flow on a moving tetrahedral mesh,
// advanced by the explicit one-step Taylor–Galerkin ALE scheme of fluid.md. One step:
//   1. artificial viscosity from U^n; 2. residual on the geometry of x^n with the mesh
//   velocity w of the step (plus the viscous pass when options.gas.viscosity is set);
//   3. U* = U^n + r / M; 4. move to x^{n+1}, recompute geometry
//   and normals; 5. boundary conditions on U*; 6. positivity check; 7. commit.
// A failed step (inverted element, negative density or pressure) throws SolverError and
// leaves the model at the last valid state, so the caller can still write it.
#include <array>
#include <chrono>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "shellflow/core/archive.h"
#include "shellflow/fluid/boundary.h"
#include "shellflow/fluid/gas.h"
#include "shellflow/fluid/geometry.h"
#include "shellflow/fluid/ordering.h"
#include "shellflow/fluid/residual.h"
#include "shellflow/fluid/shock_capturing.h"
#include "shellflow/fluid/state.h"
#include "shellflow/fluid/viscous.h"
#include "shellflow/mesh/mesh.h"

namespace shellflow::fluid {

/// Wall time of the parts of the explicit steps so far (FluidModel::timings), in seconds:
/// where a step's time goes, for the benchmarks and the run log.
struct StepTimings {
  double mesh_velocity = 0.0;  ///< w of the step (and whether the mesh moves)
  double viscosity = 0.0;      ///< artificial viscosity of the state (shock capturing)
  double element_pass = 0.0;   ///< the residual: Taylor–Galerkin + ALE terms, natural boundary term, viscous terms
  double update = 0.0;         ///< U + M^-1 r (or the consistent-mass iterations)
  double geometry = 0.0;       ///< volumes, gradients, sizes and lumped mass of the moved mesh
  double normals = 0.0;        ///< boundary face areas and wall normals of the moved mesh
  double boundary = 0.0;       ///< the boundary conditions
  double checks = 0.0;         ///< positivity check and the density-rate monitor
  long steps = 0;
  double total() const {
    return mesh_velocity + viscosity + element_pass + update + geometry + normals + boundary + checks;
  }
};

struct FluidOptions {
  IdealGas gas;              ///< gas.viscosity set: Navier–Stokes (viscous pass, no-slip walls allowed)
  double q_dif = 0.0;        ///< artificial-viscosity coefficient (paper eq. 28), 0 = off
  bool av_smoothing = true;  ///< spread nu over one element layer (fluid.md §7 step 5)
  TgVelocity tg_velocity = TgVelocity::relative;
  bool moving_mesh_correction = true;  ///< C2
  /// 0: lumped mass (default); k > 0: consistent mass by k Jacobi iterations (spec: 3;
  /// lowers the stable CFL to about 0.6x).
  int consistent_mass_iterations = 0;
  /// Slip walls through the wall's flux (docs/fluid.md "Slip walls": the wall pressure to
  /// about 0.5 % at 8 cells per wavelength, where the strong projection is 7 % off); false:
  /// the normal momentum projected at the nodes (paper eq. 29).
  bool weak_slip_walls = true;
};

/// Load of the fluid on a boundary group at its nodes (paper eq. 30, fluid.md §12). The
/// nodal p and tau can also be interpolated to other points (shell load points) and
/// combined with another normal: q = p n - tau n.
struct WallTraction {
  std::vector<Index> nodes;      ///< the group's nodes (sorted)
  std::vector<Vec3> normal;      ///< unit outward normal of the fluid domain (into the structure)
  std::vector<double> pressure;  ///< nodal p
  std::vector<Mat3> stress;      ///< nodal tau: volume-weighted mean of the adjacent elements'
  std::vector<Vec3> traction;    ///< q = p n - tau n: force per area on the structure
  std::vector<Vec3> shear;       ///< viscous part -tau n (zero for Euler)
};

/// Everything a step depends on besides the mesh and the options: restoring it and
/// stepping gives the same bits as the original run (FluidModel::snapshot / restore).
struct FluidSnapshot {
  FluidState U;            ///< conservative nodal state
  std::vector<Vec3> x, w;  ///< node positions and the mesh velocity of the last step
  double time = 0.0;
  long steps = 0;
  /// Per-node wall velocities set with set_wall_velocity, per boundary condition (empty:
  /// not set, the closure applies).
  std::vector<std::vector<Vec3>> wall_velocity;
  double density_rate = 0.0;  ///< monitor of the last step
};

class FluidModel {
 public:
  /// `mesh`: 4-node tetrahedra (renumber it with renumber_for_locality first for speed;
  /// node indices of the model are those of `mesh`). Throws InputError for a mesh that is
  /// not tet4, for bad boundary conditions or viscosity parameters, SolverError for an
  /// inverted element. `colouring`: the element blocks and colours to use (a rank's part takes
  /// restrict_colouring of the whole mesh's, for the same bits on any number of ranks); none:
  /// colour_cells with default_block_size.
  FluidModel(mesh::Mesh mesh, FluidOptions options, std::vector<BoundaryCondition> conditions,
             std::optional<CellColouring> colouring = std::nullopt);

  /// Sets every node from a primitive field, then imposes the boundary conditions.
  void set_state(const std::function<Primitive(const Vec3&)>& field);
  /// Sets the conservative state as given (no boundary conditions applied).
  void set_state(const FluidState& state);

  /// Largest stable step times `cfl`, from h_e / (|u - w| + c) and the diffusion limit
  /// h_e^2 / (2 nu) (artificial plus, for Navier–Stokes, max(mu, gamma mu / Pr) / rho);
  /// w is the mesh velocity of the last step (or set_mesh_velocity). Throws InputError for
  /// cfl outside (0, 1] (lumped mass) or (0, 0.6] (consistent mass).
  double stable_dt(double cfl);
  /// Mesh velocity used by stable_dt before the first moving step.
  void set_mesh_velocity(std::span<const Vec3> w);

  /// Velocities of the wall group `group` (slip_wall or no_slip_wall) at its nodes, one per
  /// node of mesh().group(group).nodes in that order, at the end of the next step (t^{n+1}).
  /// They replace the group's BoundaryCondition::wall_velocity closure and persist until
  /// set again (set them before each step). Slip walls impose (u - v_wall) . n = 0 along
  /// the wall normals only; along a symmetry plane's normal u . n = 0 whatever v_wall.
  /// Where two slip-wall groups meet, the later one in the condition list gives v_wall.
  /// Throws InputError naming the group for another kind or a wrong number of values.
  void set_wall_velocity(std::string_view group, std::span<const Vec3> velocity);

  /// Pressure at a node (no allocation, no bounds check).
  double pressure(Index node) const {
    const auto i = std::size_t(node);
    return options_.gas.pressure(state_.var[0][i], state_.var[1][i], state_.var[2][i], state_.var[3][i],
                                 state_.var[4][i]);
  }
  /// Pressures at `nodes` into `out` (same size; InputError otherwise). No allocation.
  void pressures(std::span<const Index> nodes, std::span<double> out) const;

  /// The state, positions, mesh velocity, time, step count and per-node wall velocities.
  FluidSnapshot snapshot() const;
  /// Back to a snapshot of this model: geometry and boundary normals recomputed from x.
  /// Stepping from it then repeats the original steps bit for bit. Throws InputError for
  /// sizes that do not match the mesh, SolverError for an inverted element in x.
  void restore(const FluidSnapshot& snapshot);
  /// The snapshot into / out of a checkpoint (core/archive.h). Throws Error for a checkpoint
  /// of another mesh.
  void save(ArchiveWriter& out) const;
  void restore(ArchiveReader& in);

  /// One step on a fixed mesh.
  void step(double dt);
  /// One step during which the nodes move to `x_next`. `w` is the mesh velocity of the
  /// step; empty: w = (x_next - x) / dt.
  void step(double dt, std::span<const Vec3> x_next, std::span<const Vec3> w = {});

  /// One step towards a steady state with local time steps dt_a = cfl min_{e∋a} dt_e
  /// (fluid.md §4.3); fixed mesh. time() advances by the smallest step.
  void step_local(double cfl);

  /// A rank's part of a distributed mesh (docs/parallel.md): the model's mesh is the rank's
  /// local mesh (owned nodes, then ghosts; every cell of an owned node), best with the whole
  /// mesh's colouring restricted to it (restrict_colouring: the same bits on any rank count).
  /// `exchange` sets the ghost entries of nodal fields from their owners; it is called after the
  /// artificial viscosity's gradient recovery and smoothing, on the new state after the
  /// boundary conditions and on the nodal viscosity of the frames, so every owned node advances
  /// as in one process. `min` is the minimum over the ranks (the stable time step, whether the
  /// mesh moves); `sum` a sum over the ranks whose bits are the same on every rank (the density
  /// rate over the `owned` first nodes, so that every rank takes the same steady-state
  /// decision); `first_error` the agreement on a failed step (mpi::Communicator::first_error):
  /// an inverted element or a non-physical state found on one rank fails the step on every
  /// rank with the same line, after the step's exchanges, so no rank waits for another. Lumped
  /// mass only. Every rank must call step, stable_dt and nodal_artificial_viscosity in the same
  /// order.
  struct Distribution {
    GhostExchange exchange;
    std::function<double(double)> min;
    std::function<double(double)> sum;
    std::function<std::string(const std::string&)> first_error;
    Index owned = 0;
  };
  /// Throws InputError with consistent mass (its sweeps would need an exchange each).
  void set_distribution(Distribution distribution);

  /// RMS over the nodes of d(rho)/dt in the last step (steady convergence monitor).
  double density_rate() const { return density_rate_; }

  double time() const { return time_; }
  long steps() const { return steps_; }
  const FluidState& state() const { return state_; }
  Primitive primitive(Index node) const { return to_primitive(options_.gas, state_.get(node)); }
  std::span<const Vec3> positions() const { return x_; }
  std::span<const Vec3> mesh_velocity() const { return w_; }
  const mesh::Mesh& mesh() const { return mesh_; }
  const FluidOptions& options() const { return options_; }
  const TetGeometry& geometry() const { return geometry_; }
  const BoundarySet& boundaries() const { return boundaries_; }
  int num_colours() const { return colours_.num_colours(); }
  Index num_blocks() const { return colours_.num_blocks(); }
  /// Force the gas exerts on the boundary group `group` (inviscid part of paper eq. 30):
  /// F = integral of p n dA, n the outward normal of the fluid domain (pointing into the
  /// structure), p linear on each face. Throws InputError for an unknown group.
  Vec3 pressure_force(std::string_view group) const;
  /// Force of the full Navier–Stokes stress on the group (paper eq. 30):
  /// F = integral of (p n - tau n) dA with the nodal p and tau of wall_traction linear on
  /// each face. Equals pressure_force for Euler. Throws InputError for an unknown group.
  Vec3 viscous_force(std::string_view group) const;
  /// Nodal load q = p n - tau n on the group: nodal p, nodal tau the volume-weighted mean
  /// of the adjacent elements' stresses, n the area-weighted normal of the group's faces.
  WallTraction wall_traction(std::string_view group) const;
  /// Viscous traction -tau n (force per area of the gas on the structure, n out of the
  /// fluid) at the nodes of the no-slip group `group`, in mesh().group(group).nodes order,
  /// into `out` (that size; InputError otherwise). The consistent boundary flux: the
  /// reaction of the viscous residual at each node, F_a = -sum_e V_e tau_e grad N_a over the
  /// elements around it, divided by the node's share of the wall (integral of N_a dA over
  /// the group's faces and the coplanar no-slip faces next to them: the same wall going on).
  /// Exact for a linear profile, second order for a curved one (the one-sided gradient of the
  /// wall elements is first order: fluid.md); the volume term N_a div(tau) is left out, an
  /// error (h/2)|rho a_wall + grad p| per area. Where another boundary meets the wall at an
  /// angle (its flux would be in the reaction), the wall elements' one-sided stress instead;
  /// on a symmetry plane the component across it is removed (zero by symmetry). Zero for
  /// Euler. One element flux per element touching the group (the element and face lists
  /// are built on the first call).
  void wall_shear(std::string_view group, std::span<Vec3> out);
  /// Artificial viscosity nu (m^2/s, paper eq. 28) of the current state at the nodes: the
  /// volume-weighted mean of the adjacent elements' values (for output).
  std::vector<double> nodal_artificial_viscosity();
  /// Where the steps' time went (every step; reset_timings() starts again).
  const StepTimings& timings() const { return timings_; }
  void reset_timings() { timings_ = {}; }
  /// Bytes held by the model's arrays (mesh copy, geometry, states, work arrays).
  std::size_t memory_bytes() const;

 private:
  /// Ghost entries of a state from their owners (a distributed model; else nothing).
  void exchange(FluidState& u);

  // The step and its stages (fluid_model.cpp: advance).
  void advance(double dt, std::span<const Vec3> x_next, std::span<const Vec3> w, bool local);
  /// Adds the time since the last lap to a part of timings_.
  struct StepClock {
    std::chrono::steady_clock::time_point last = std::chrono::steady_clock::now();
    void lap(double& part);
  };
  void check_step_input(double dt, std::span<const Vec3> x_next, std::span<const Vec3> w) const;
  /// w_next_ of the step; returns whether the mesh moves on any rank.
  bool step_mesh_velocity(double dt, std::span<const Vec3> x_next, std::span<const Vec3> w);
  /// next_geometry_ and the wall normals at x_next; on ranks a failure is returned (to be
  /// agreed on after the exchange), in one process thrown.
  std::string move_geometry(std::span<const Vec3> x_next, bool& normals_moved, StepClock& clock);
  /// Positivity of next_state_ and the agreement on a failure; throws SolverError with the
  /// normals restored.
  void check_next_state(double t_next, std::string failure, bool normals_moved);
  /// The steady-state monitor: RMS of d(rho)/dt over the (owned) nodes.
  double step_density_rate(double dt, bool local);
  void commit_step(double t_next, std::span<const Vec3> x_next, bool moves);
  void check_cfl(double cfl) const;
  /// next_state_ = U^n + M^-1 r (lumped, or the consistent mass's sweeps with the constraints
  /// of the values at t_end imposed in each).
  void apply_mass_inverse(const FluidState& r, double t_end, std::span<const Vec3> x_next, const FluidState& base,
                          FluidState& out);
  /// The step's residual into residual_: element pass, natural boundary term, the weak
  /// walls' flux and the viscous terms.
  void assemble_step_residual(const ResidualParameters& p, std::span<const Vec3> w_step);
  void update_viscosity();
  /// Element diffusivities for the time-step limit (viscosity_ itself for Euler).
  std::span<const double> time_step_diffusivity();
  void check_positivity(const FluidState& u, double t) const;
  ElementLoop loop() const { return {tets_, colours_.block_offsets, colours_.colour_offsets}; }

  /// What wall_shear needs of a group (topology only): the elements with a node in it and the
  /// no-slip faces with a node in it, each with its nodes' places in the group (-1: not in it).
  struct WallShearStencil {
    std::string group;
    std::vector<std::pair<Index, std::array<Index, 4>>> elements;
    std::vector<std::pair<BoundaryFace, std::array<Index, 3>>> own_faces;  ///< the group's
    /// The group's faces and the coplanar no-slip faces next to them (the same wall going on).
    std::vector<std::pair<BoundaryFace, std::array<Index, 3>>> area_faces;
    std::vector<std::pair<BoundaryFace, std::array<Index, 3>>> symmetry_faces;
    std::vector<char> corner;  ///< per node: another boundary meets the wall at an angle there
  };
  /// A no-slip face whose normal is within about 20 degrees of the wall's own continues it.
  static constexpr double kCoplanarWall = 0.94;
  const WallShearStencil& shear_stencil(std::string_view group);

  mesh::Mesh mesh_;
  FluidOptions options_;
  std::vector<WallShearStencil> shear_stencils_;
  std::vector<Index> tets_;  // connectivity in colour order
  CellColouring colours_;
  std::vector<Vec3> x_, w_, w_next_;
  TetGeometry geometry_, next_geometry_;
  BoundarySet boundaries_;
  FluidState state_, next_state_, residual_, increment_, mass_work_;
  ShockCapturingWorkspace av_work_;
  std::vector<double> viscosity_;
  std::vector<double> diffusivity_;  // artificial + physical, for the time-step limit
  NodalVelocityTemperature viscous_work_;
  std::vector<std::array<double, 4>> time_step_work_;
  std::vector<double> element_dt_, nodal_dt_;
  std::vector<double> rate_sums_;  // partial sums of the density-rate monitor
  double density_rate_ = 0.0;
  StepTimings timings_;
  Distribution distribution_;
  bool viscosity_valid_ = false;
  double time_ = 0.0;
  long steps_ = 0;
};

}  // namespace shellflow::fluid
