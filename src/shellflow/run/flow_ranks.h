#pragma once
// The one owner of a flow's distribution over MPI ranks in a run (docs/parallel.md): this
// rank's part of the fluid mesh, its ghost exchange, the gathers from the owners, the
// checkpoint in the whole mesh's form and the rank's pieces of the fluid frames. The flow run
// and the coupled run (and the identification run, through it) hold one and use it the same
// way.
#include <optional>
#include <span>

#include "shellflow/core/archive.h"
#include "shellflow/coupling/flow.h"
#include "shellflow/fluid/fluid_model.h"
#include "shellflow/mpi/communicator.h"
#include "shellflow/mpi/halo_exchange.h"
#include "shellflow/run/fluid_pieces.h"
#include "shellflow/setup/fluid_setup.h"

namespace shellflow::run {

class FlowRanks {
 public:
  /// `comm` and `part` (this rank's part of the renumbered fluid mesh) must outlive it.
  FlowRanks(const mpi::Communicator& comm, const setup::FlowPart& part);
  FlowRanks(const FlowRanks&) = delete;
  FlowRanks& operator=(const FlowRanks&) = delete;

  /// Runs `flow` (the model of this rank's part) over the ranks: its ghost exchange and
  /// reductions.
  void attach(fluid::FluidModel& flow);
  /// The same for a coupled run's flow, and its FlowModel's gathers and checkpoint.
  void attach(fluid::FluidModel& flow, coupling::FlowModel& model);
  /// The flow's state in the whole mesh's form (a checkpoint that restarts on any number of
  /// ranks), and back. Every rank calls them.
  void save(const fluid::FluidModel& flow, ArchiveWriter& out) const;
  void restore(fluid::FluidModel& flow, ArchiveReader& in) const;
  /// The rank's pieces of the fluid frames and the probes' values from their owners.
  FluidPieces pieces(const fluid::FluidModel& flow, std::span<const Index> new_index, const io::ProbeSet& probes) const;

  const setup::FlowPart& part() const { return part_; }

 private:
  const mpi::Communicator& comm_;
  const setup::FlowPart& part_;
  mpi::HaloExchange halo_;
};

}  // namespace shellflow::run
