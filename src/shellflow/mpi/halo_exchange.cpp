#include "shellflow/mpi/halo_exchange.h"

#include <fmt/format.h>
#include <mpi.h>

#include "shellflow/core/error.h"

namespace shellflow::mpi {

HaloExchange::HaloExchange(const Communicator& comm, const mesh::LocalPart& part)
    : comm_(comm), neighbours_(part.neighbours) {
  if (part.rank != comm.rank())
    throw InputError(fmt::format("halo exchange: the local part of rank {} given to rank {}", part.rank, comm.rank()));
  for (const auto& n : neighbours_)
    if (n.rank < 0 || n.rank >= comm.size() || n.rank == comm.rank())
      throw InputError(fmt::format("halo exchange: neighbour rank {} of rank {} is not another rank of {}", n.rank,
                                   comm.rank(), comm.size()));
  send_buffers_.resize(neighbours_.size());
  receive_buffers_.resize(neighbours_.size());
}

void HaloExchange::exchange(std::span<double* const> fields) {
  const std::size_t nf = fields.size();
  if (nf == 0 || neighbours_.empty()) return;
  constexpr int tag = 2141;
  std::vector<MPI_Request> requests;
  requests.reserve(2 * neighbours_.size());
  for (std::size_t k = 0; k < neighbours_.size(); ++k) {
    const auto& nb = neighbours_[k];
    auto& in = receive_buffers_[k];
    in.resize(nb.receive.size() * nf);
    requests.emplace_back();
    MPI_Irecv(in.data(), int(in.size()), MPI_DOUBLE, nb.rank, tag, MPI_COMM_WORLD, &requests.back());
  }
  for (std::size_t k = 0; k < neighbours_.size(); ++k) {
    const auto& nb = neighbours_[k];
    auto& out = send_buffers_[k];
    out.resize(nb.send.size() * nf);
    // Field by field: [f0 of every node, f1 of every node, ...].
    for (std::size_t f = 0; f < nf; ++f)
      for (std::size_t i = 0; i < nb.send.size(); ++i) out[f * nb.send.size() + i] = fields[f][nb.send[i]];
    requests.emplace_back();
    MPI_Isend(out.data(), int(out.size()), MPI_DOUBLE, nb.rank, tag, MPI_COMM_WORLD, &requests.back());
  }
  if (MPI_Waitall(int(requests.size()), requests.data(), MPI_STATUSES_IGNORE) != MPI_SUCCESS)
    throw Error(fmt::format("MPI: the halo exchange of rank {} failed", comm_.rank()));
  for (std::size_t k = 0; k < neighbours_.size(); ++k) {
    const auto& nb = neighbours_[k];
    const auto& in = receive_buffers_[k];
    for (std::size_t f = 0; f < nf; ++f)
      for (std::size_t i = 0; i < nb.receive.size(); ++i) fields[f][nb.receive[i]] = in[f * nb.receive.size() + i];
  }
}

}  // namespace shellflow::mpi
