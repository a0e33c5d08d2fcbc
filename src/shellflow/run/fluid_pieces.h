#pragma once
// A distributed flow's outputs (docs/parallel.md): every rank's piece of the fluid frames and
// the probe values of the flow, gathered from the ranks owning the probed nodes so that every
// rank samples the same numbers as a run in one process.
#include <functional>
#include <span>
#include <string_view>
#include <vector>

#include "shellflow/io/probes.h"
#include "shellflow/mesh/mesh.h"
#include "shellflow/mpi/communicator.h"
#include "shellflow/setup/fluid_setup.h"

namespace shellflow::run {

/// The fluid frames' piece of one rank and the maps from case nodes to its model.
struct FluidPieces {
  const mpi::Communicator* ranks = nullptr;
  mesh::Mesh piece;                   ///< the cells whose first node the rank owns, on the nodes they use
  std::vector<Index> piece_to_model;  ///< model node of each piece node
  std::vector<Index> case_to_model;   ///< model node of each case node; -1: not on this rank
  std::vector<int> case_owner;        ///< owner rank of each case node
  std::vector<Index> probed;          ///< the case nodes the probes read (sorted)
};

/// The pieces of `model`, rank ranks.rank()'s part `part` of a flow whose case nodes are the
/// whole mesh's nodes new_index, for the probes `probes`.
FluidPieces make_fluid_pieces(const fluid::FluidModel& model, const setup::FlowPart& part,
                              std::span<const Index> new_index, const mpi::Communicator& ranks,
                              const io::ProbeSet& probes);

/// The probed nodes' values of some nodal quantities, gathered from their owners: refresh()
/// (on every rank at once) collects them, views() gives them to the probes by case node.
class ProbeGather {
 public:
  struct Quantity {
    std::string_view name;
    int components = 1;
  };
  /// value(q, model node, out): quantity q's components at a node this rank owns.
  using Value = std::function<void(std::size_t q, Index model_node, double* out)>;
  ProbeGather(const FluidPieces& pieces, std::vector<Quantity> quantities, Value value);
  void refresh();
  /// One view per quantity of mesh "fluid"; at() reads the gathered values of probed nodes.
  std::vector<io::FieldView> views() const;

 private:
  const double* at(Index case_node) const;
  const FluidPieces& pieces_;
  std::vector<Quantity> quantities_;
  Value value_;
  std::vector<std::size_t> offset_;  ///< of each quantity in a node's values
  std::size_t per_node_ = 0;
  std::vector<double> values_;  ///< per_node_ values per probed node, in pieces_.probed order
  std::vector<int> owners_;     ///< of the probed nodes
};

}  // namespace shellflow::run
