#pragma once
// The exchange of ghost-node values between ranks (docs/parallel.md): every rank holds its
// owned nodes and one ghost layer (mesh::LocalPart); after a rank has updated its owned
// nodes, exchange() sets each ghost node to the value its owner computed. One message per
// neighbour and direction, all fields of a call in it.
#include <span>
#include <vector>

#include "shellflow/mesh/partition.h"
#include "shellflow/mpi/communicator.h"

namespace shellflow::mpi {

class HaloExchange {
 public:
  /// The send and receive lists of `part` (make_local_part of this rank). The part must be
  /// this rank's (part.rank == comm.rank()); InputError otherwise.
  HaloExchange(const Communicator& comm, const mesh::LocalPart& part);

  /// For every field (one value per local node, part.nodes order): the ghost entries set
  /// from their owners' owned entries. Every rank calls it with the same number of fields.
  void exchange(std::span<double* const> fields);

  std::size_t num_neighbours() const { return neighbours_.size(); }

 private:
  const Communicator& comm_;
  std::vector<mesh::NeighbourLists> neighbours_;
  std::vector<std::vector<double>> send_buffers_, receive_buffers_;
};

}  // namespace shellflow::mpi
