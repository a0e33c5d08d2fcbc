#pragma once
// The one checkpoint layout of a flow's snapshot (FluidSnapshot): its per-node fields in the
// whole mesh's node order, so that a checkpoint restarts on any number of MPI ranks, or in one
// process. The layout of the fields is written once, here; where the values come from is a
// SnapshotLayout: in one process the model's own nodes are the whole mesh (no layout), on
// ranks the owners' values are gathered to rank 0 and every rank takes its nodes from the
// whole (mpi/flow_distribution.h).
//
//   5 x vector<double>   U (rho, rho u, rho v, rho w, rho E), per whole node
//   vector<Vec3> x, w    positions and mesh velocities, per whole node
//   double time, long steps
//   u64 count, then per boundary condition vector<Vec3>: the wall velocities set per node
//                        of its group, in the whole group's (sorted) node order; empty: unset
//   double density_rate
#include <span>
#include <string>
#include <vector>

#include "shellflow/core/archive.h"
#include "shellflow/fluid/fluid_model.h"

namespace shellflow::fluid {

/// Where a snapshot's per-node values come from and go to.
class SnapshotLayout {
 public:
  virtual ~SnapshotLayout() = default;
  /// The whole field (`components` values per node, whole node order) of this process's
  /// values (`components` per local node). A process that does not write may return its own.
  virtual std::vector<double> gather(std::span<const double> local, int components) const = 0;
  /// The whole group's values (sorted whole nodes) of values set per node of a group
  /// (`group`: its local nodes); empty when no process has any.
  virtual std::vector<Vec3> gather_group(std::span<const Index> group, std::span<const Vec3> local) const = 0;
  /// The whole mesh's node count.
  virtual std::size_t whole_nodes() const = 0;
  /// This process's values (per local node) of a whole field.
  virtual std::vector<double> scatter(std::span<const double> whole, int components) const = 0;
  /// The values of a group's local nodes from the whole group's (`what` names them in an
  /// error: a count that does not match throws).
  virtual std::vector<Vec3> scatter_group(std::span<const Index> group, std::span<const Vec3> whole, ArchiveReader& in,
                                          const std::string& what) const = 0;
};

/// The model's snapshot in the layout above (`layout` null: the model's mesh is the whole).
void write_snapshot(const FluidModel& model, ArchiveWriter& out, const SnapshotLayout* layout = nullptr);
/// The inverse: reads, checks the sizes (Error naming the field for a checkpoint of another
/// mesh) and restores the model.
void read_snapshot(FluidModel& model, ArchiveReader& in, const SnapshotLayout* layout = nullptr);

}  // namespace shellflow::fluid
