#include "shellflow/dist/flow_distribution.h"

namespace shellflow::dist {

fluid::FluidModel::Distribution flow_distribution(const Communicator& comm, HaloExchange& halo,
                                                  const mesh::LocalPart& part) {
  return {[&halo](std::span<double* const> fields) { halo.exchange(fields); },
          [&comm](double x) { return comm.min(x); }, [&comm](double x) { return comm.sum_in_rank_order(x); },
          [&comm](const std::string& message) { return comm.first_error(message); }, part.num_owned};
}

}  // namespace shellflow::dist
