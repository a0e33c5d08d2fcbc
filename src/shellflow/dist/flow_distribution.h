#pragma once
// A flow model on a rank's part of the mesh (fluid::FluidModel::set_distribution) over the
// world's ranks: the ghost exchange of the rank's local part and the ranks' reductions.
#include "shellflow/dist/communicator.h"
#include "shellflow/dist/halo_exchange.h"
#include "shellflow/fluid/fluid_model.h"

namespace shellflow::dist {

/// The distribution of a model on `part` (this rank's local part): exchange through `halo`,
/// min, sum in rank order and first_error over `comm`, `part.num_owned` owned nodes. `comm` and
/// `halo` must outlive the model.
fluid::FluidModel::Distribution flow_distribution(const Communicator& comm, HaloExchange& halo,
                                                  const mesh::LocalPart& part);

}  // namespace shellflow::dist
