#include "shellflow/run/flow_ranks.h"

#include "shellflow/mpi/flow_distribution.h"

namespace shellflow::run {

FlowRanks::FlowRanks(const mpi::Communicator& comm, const setup::FlowPart& part)
    : comm_(comm), part_(part), halo_(comm, part.local) {}

void FlowRanks::attach(fluid::FluidModel& flow) {
  flow.set_distribution(mpi::flow_distribution(comm_, halo_, part_.local));
}

void FlowRanks::attach(fluid::FluidModel& flow, coupling::FlowModel& model) {
  attach(flow);
  const mpi::Communicator* comm = &comm_;
  model.set_distribution({part_.local.nodes, part_.node_owner, comm_.rank(),
                          [comm](std::span<const int> owners, std::span<double> values) {
                            mpi::gather_from_owners(*comm, owners, values);
                          },
                          [this, &flow](ArchiveWriter& out) { save(flow, out); },
                          [this, &flow](ArchiveReader& in) { restore(flow, in); }});
}

void FlowRanks::save(const fluid::FluidModel& flow, ArchiveWriter& out) const {
  mpi::save_whole(flow, comm_, part_.local, part_.whole_nodes, out);
}

void FlowRanks::restore(fluid::FluidModel& flow, ArchiveReader& in) const {
  mpi::restore_whole(flow, comm_, part_.local, part_.whole_nodes, in);
}

FluidPieces FlowRanks::pieces(const fluid::FluidModel& flow, std::span<const Index> new_index,
                              const io::ProbeSet& probes) const {
  return make_fluid_pieces(flow, part_, new_index, comm_, probes);
}

}  // namespace shellflow::run
