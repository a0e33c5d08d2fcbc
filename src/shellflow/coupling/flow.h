#pragma once
// The flow as an aerodynamic model of the partitioned driver (coupling.md, time stepping,
// step 3): in every shell step [t_i, t_i+1], n_sub fluid steps; in each, the shell motion of
// the Hermite window moves the space mesh and through it the fluid nodes, the wall velocity
// of the slip condition (paper eq. 29) is the Hermite derivative at the wet nodes, and one
// explicit fluid step follows. The last sub-step lands exactly on t_i+1.
//
// Without a fluid model (a case with mesh motion but no flow: the paper's mesh-motion
// tests) only the fluid mesh is moved, with the same sub-steps, and an inverted element
// stops the run.
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "shellflow/coupling/aerodynamics.h"
#include "shellflow/coupling/interface_maps.h"
#include "shellflow/fluid/fluid_model.h"
#include "shellflow/mesh/mesh.h"
#include "shellflow/motion/mesh_mover.h"

namespace shellflow::coupling {

struct FlowModelOptions {
  int substeps = 0;  ///< fluid steps per shell step; 0: auto, from the stable step
  double cfl = 0.5;  ///< of the auto rule n_sub = ceil(dt_s / (cfl dt_stable))
  /// Mesh velocity of the fluid step: false (default) w = (x^m - x^{m-1}) / dt_f, which
  /// keeps a uniform flow exactly uniform; true: the interpolated velocity of eq. 32.
  bool interpolated_mesh_velocity = false;
  double reference_pressure = 0.0;  ///< p_ref subtracted from the loads (the free-stream pressure)
};

class FlowModel final : public AerodynamicModel {
 public:
  /// `fluid_mesh`: the mesh the flow and the mover were built on (renumbered, wall snapped);
  /// `flow`: null for a mesh-motion-only run. The model keeps references to mesh, motion
  /// and mover.
  FlowModel(const mesh::Mesh& fluid_mesh, std::unique_ptr<fluid::FluidModel> flow,
            std::unique_ptr<motion::FluidMeshMover> mover, ShellStepMotion& motion, WallNodeMap wall,
            LoadPointMap loads, FlowModelOptions options);

  std::string name() const override { return flow_ ? "euler" : "mesh_motion"; }
  /// On a failure (SolverError) the flow, the fluid mesh and the space mesh are put back to
  /// their state at the start of the step before the error propagates.
  FlowStepReport advance(const ShellStepMotion& motion, double t_end) override;
  void pressure_rise(const Eigen::VectorXd& u, const Eigen::VectorXd& v, std::span<double> dp) override;
  std::span<const double> sign() const override { return loads_.sign; }
  /// A no-slip wet wall of a viscous flow passes the shear.
  bool has_shear() const override { return has_shear_; }
  /// The wall shear at the wet nodes (FluidModel::wall_shear: the consistent boundary flux),
  /// interpolated to the load points with the pressure's weights.
  void shear(std::span<Vec3> out) override;
  /// Pressure (minus the reference) and shear on the wet faces, linear on each face; the
  /// shear is that of the last exchange (shear()).
  std::optional<Vec3> fluid_side_force() const override;
  /// Time, fluid node positions and mesh velocities, the mover's and the flow's states.
  void save(ArchiveWriter& out) const override { save_state(out, true); }
  void restore(ArchiveReader& in) override { restore_state(in, true); }

  /// The flow distributed over ranks (docs/parallel.md): the model's flow runs on this rank's
  /// part of the fluid mesh (its node i is node whole_of_local[i] of the mesh this FlowModel
  /// was built on), while the mesh motion, the wall map and the load map stay whole on every
  /// rank (replicated: the same bits everywhere). `gather(nodes, values)`: values[k] of whole
  /// node nodes[k] from the rank owning it (each rank fills those it owns), on every rank.
  /// `save_flow` / `restore_flow`: the flow's state in the whole mesh's form
  /// (mpi/flow_distribution.h). Throws InputError for a wall with shear (viscous coupling is
  /// not distributed yet).
  struct Distribution {
    std::vector<Index> whole_of_local;
    std::vector<int> owner;  ///< owner rank of every whole node
    int rank = 0;
    std::function<void(std::span<const int> owners, std::span<double> values)> gather;
    std::function<void(ArchiveWriter&)> save_flow;
    std::function<void(ArchiveReader&)> restore_flow;
  };
  void set_distribution(Distribution distribution);

  /// Sub-steps the next shell step of length dt needs (auto) or gets (fixed); throws
  /// SolverError naming the time and the n_sub needed when a fixed count is too small.
  FlowStepReport substeps_for(double dt);

  double time() const { return time_; }
  const fluid::FluidModel* flow() const { return flow_.get(); }
  fluid::FluidModel* flow() { return flow_.get(); }
  const motion::FluidMeshMover& mover() const { return *mover_; }
  motion::FluidMeshMover& mover() { return *mover_; }
  std::span<const Vec3> positions() const { return x_; }
  /// Mesh velocity: with a flow and w = Δx/Δt, that of the flow's last sub-step (the mover
  /// then moves positions only); else the mover's (interpolated) velocity.
  std::span<const Vec3> mesh_velocity() const { return w_; }
  const mesh::Mesh& mesh() const { return mesh_; }
  const WallNodeMap& wall_map() const { return wall_; }

 private:
  const mesh::Mesh& mesh_;
  std::unique_ptr<fluid::FluidModel> flow_;
  std::unique_ptr<motion::FluidMeshMover> mover_;
  WallNodeMap wall_;
  LoadPointMap loads_;
  std::vector<WetFace> faces_;
  FlowModelOptions options_;
  int wall_handle_ = -1;
  double time_ = 0.0;
  std::vector<Vec3> x_, w_, wall_displacement_, wall_velocity_;
  std::vector<double> node_pressure_;
  bool has_shear_ = false;
  std::vector<Vec3> wall_shear_;         ///< at wall_.nodes, of the last shear()
  std::vector<std::size_t> shear_slot_;  ///< per loads_.fluid_nodes entry: its place in wall_.nodes
  void save_mark(ArchiveWriter& out) const override { save_state(out, false); }
  void restore_mark(ArchiveReader& in) override { restore_state(in, false); }
  /// `whole`: on ranks, the flow's state in the whole mesh's form (a checkpoint); else (a mark)
  /// the rank's own part.
  void save_state(ArchiveWriter& out, bool whole) const;
  void restore_state(ArchiveReader& in, bool whole);
  /// Distributed: the pressures of whole nodes from their owners (every rank the same).
  void gather_pressures(std::span<const Index> nodes, std::span<double> out) const;
  std::optional<Distribution> dist_;
  std::vector<Index> local_of_whole_;         ///< -1: not on this rank
  std::vector<std::size_t> local_wall_slot_;  ///< per node of the local wall group: its place in wall_.nodes
  std::vector<Vec3> local_x_, local_w_, local_wall_velocity_;
};

}  // namespace shellflow::coupling
