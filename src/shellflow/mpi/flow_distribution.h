#pragma once
// A flow model on a rank's part of the mesh (fluid::FluidModel::set_distribution) over the
// world's ranks: the ghost exchange of the rank's local part and the ranks' reductions.
#include "shellflow/core/archive.h"
#include "shellflow/fluid/fluid_model.h"
#include "shellflow/mpi/communicator.h"
#include "shellflow/mpi/halo_exchange.h"

namespace shellflow::mpi {

/// The distribution of a model on `part` (this rank's local part): exchange through `halo`,
/// min, sum in rank order and first_error over `comm`, `part.num_owned` owned nodes. `comm` and
/// `halo` must outlive the model.
fluid::FluidModel::Distribution flow_distribution(const Communicator& comm, HaloExchange& halo,
                                                  const mesh::LocalPart& part);

/// A distributed model's state in the form FluidModel::save gives it for the whole mesh (the
/// nodes in the order of the mesh `part` was cut from, `whole_nodes` of them): gathered from
/// the owners, complete on rank 0 (the others put the same layout with their part only, for
/// the writes they skip: core/output_file.h). A checkpoint of it restarts on any number of
/// ranks, or in one process. Wall velocities set per node (a coupled run's) go in the whole
/// group's node order. Every rank calls it.
void save_whole(const fluid::FluidModel& model, const Communicator& comm, const mesh::LocalPart& part,
                Index whole_nodes, ArchiveWriter& out);
/// The inverse on every rank: the whole state read, this rank's nodes taken.
void restore_whole(fluid::FluidModel& model, const Communicator& comm, const mesh::LocalPart& part, Index whole_nodes,
                   ArchiveReader& in);

}  // namespace shellflow::mpi
