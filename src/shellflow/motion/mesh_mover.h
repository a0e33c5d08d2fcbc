#pragma once
// Fluid mesh movers: given the motion of the moving boundary, the fluid node positions and
// mesh velocities at time t. Three methods behind one interface, selectable in a case file:
// the space mesh (the paper's method), direct inverse-distance weighting on every fluid node,
// and Laplacian smoothing on the fluid mesh.
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "shellflow/core/archive.h"
#include "shellflow/mesh/mesh.h"
#include "shellflow/motion/boundary_motion.h"
#include "shellflow/motion/space_mesh.h"

namespace shellflow::motion {

/// Which fluid-mesh boundaries move, which are fixed and which slide (by group name; the
/// same names in the fluid and the space mesh).
struct BoundaryGroups {
  std::vector<std::string> interface_groups;
  std::vector<std::string> fixed_groups;
  std::vector<std::string> sliding_groups;
};

class FluidMeshMover {
 public:
  virtual ~FluidMeshMover() = default;
  /// Fluid node positions x and mesh velocities w at time t; w empty: positions only (the
  /// flow takes w = Δx/Δt; the space mesh then interpolates half the data).
  virtual void update(double time, std::span<Vec3> x, std::span<Vec3> w) = 0;
  virtual std::string name() const = 0;
  /// Bytes of the mover's own data (weights, locations, matrices).
  virtual std::size_t memory_bytes() const = 0;
  /// Checkpoint of what the next update() reads besides its time (core/archive.h); the
  /// algebraic movers keep nothing between updates.
  virtual void save(ArchiveWriter&) const {}
  virtual void restore(ArchiveReader&) {}
};

/// Node sets of a fluid mesh's boundary groups (interface > fixed > sliding precedence), with
/// the sliding nodes' plane normals.
struct FluidBoundaryNodes {
  std::vector<Index> interface_nodes, fixed_nodes, sliding_nodes;
  std::vector<std::array<Vec3, 2>> sliding_normals;  ///< per sliding node
  std::vector<double> interface_areas, fixed_areas;  ///< lumped boundary areas
};
FluidBoundaryNodes classify_fluid_boundary(const mesh::Mesh& fluid, const BoundaryGroups& groups);

/// The paper's method: the space mesh moved by IDW of the interface samples, the fluid
/// nodes interpolated at fixed parametric coordinates, the fluid interface nodes placed
/// exactly on the boundary motion.
class SpaceMeshMover final : public FluidMeshMover {
 public:
  /// `samples`/`sample_areas`: the IDW samples of the interface (the shell's nodes); empty:
  /// the fluid mesh's interface nodes with their lumped areas.
  SpaceMeshMover(const mesh::Mesh& fluid, const mesh::Mesh& space, SpaceMeshOptions options, BoundaryMotion& motion,
                 std::vector<Vec3> samples = {}, std::vector<double> sample_areas = {});
  void update(double time, std::span<Vec3> x, std::span<Vec3> w) override;
  std::string name() const override { return "space_mesh"; }
  std::size_t memory_bytes() const override;

  const SpaceMesh& space_mesh() const { return space_; }
  const LocationReport& location_report() const { return report_; }

 private:
  /// The motion's time modes moved through the space mesh (BoundaryMotion::num_time_modes):
  /// per mode the space-mesh node displacements and the fluid node displacements, for the
  /// window `window`.
  struct ModeFields {
    std::uint64_t window = 0;
    int modes = 0;
    std::vector<std::vector<Vec3>> space, fluid;
  };
  void move_time_modes();
  SpaceMesh space_;
  BoundaryMotion& motion_;
  ModeFields modes_;
  LocationReport report_;
  std::vector<Index> fluid_interface_;
  int space_handle_ = -1, sample_handle_ = -1, fluid_handle_ = -1;
  std::vector<Vec3> iu_, iv_, su_, sv_, fu_, fv_, space_u_, space_v_;  // work arrays
  std::vector<Vec3> fluid_initial_;
};

/// Baseline: equation 33 evaluated at every fluid node, the sums over the fluid mesh's own
/// interface and fixed-boundary nodes (O(N_fluid x N_boundary) per step, nothing stored).
class DirectIdwMover final : public FluidMeshMover {
 public:
  DirectIdwMover(const mesh::Mesh& fluid, const BoundaryGroups& groups, BoundaryMotion& motion,
                 double interface_exponent = 4.0, double fixed_exponent = 4.0,
                 IdwWeighting weighting = IdwWeighting::plain);
  void update(double time, std::span<Vec3> x, std::span<Vec3> w) override;
  std::string name() const override { return "direct_idw"; }
  std::size_t memory_bytes() const override;

 private:
  const mesh::Mesh& fluid_;
  FluidBoundaryNodes boundary_;
  BoundaryMotion& motion_;
  double e1_, e2_;
  IdwWeighting weighting_;
  std::vector<Index> free_nodes_;  ///< interior + sliding
  std::vector<std::array<Vec3, 2>> free_normals_;
  int handle_ = -1;
  std::vector<Vec3> iu_, iv_;
};

}  // namespace shellflow::motion
