#include "shellflow/run/fluid_pieces.h"

#include <fmt/format.h>

#include <algorithm>

#include "shellflow/core/error.h"

namespace shellflow::run {

FluidPieces make_fluid_pieces(const fluid::FluidModel& model, const setup::FlowPart& part,
                              std::span<const Index> new_index, const mpi::Communicator& ranks,
                              const io::ProbeSet& probes) {
  const mesh::LocalPart& local = part.local;
  const mesh::Mesh& model_mesh = model.mesh();
  FluidPieces p;
  p.ranks = &ranks;
  // Whole node -> model node.
  std::vector<Index> model_of(std::size_t(part.whole_nodes), -1);
  for (std::size_t i = 0; i < local.nodes.size(); ++i) model_of[std::size_t(local.nodes[i])] = Index(i);
  p.case_to_model.resize(new_index.size());
  p.case_owner.resize(new_index.size());
  for (std::size_t i = 0; i < new_index.size(); ++i) {
    p.case_to_model[i] = model_of[std::size_t(new_index[i])];
    p.case_owner[i] = part.node_owner[std::size_t(new_index[i])];
  }
  // The piece: the model's cells whose first node the rank owns (each cell has one such rank,
  // and holds the cell: it is a cell of an owned node), on the model nodes they use.
  p.piece.name = model_mesh.name;
  p.piece.source = model_mesh.source;
  p.piece.cells.type = model_mesh.cells.type;
  std::vector<Index> piece_of(model_mesh.nodes.size(), -1);
  for (Index c = 0; c < model_mesh.num_cells(); ++c) {
    const auto cell = model_mesh.cells.element(c);
    if (cell[0] >= local.num_owned) continue;  // owned nodes come first
    for (const Index k : cell) {
      Index& n = piece_of[std::size_t(k)];
      if (n < 0) {
        n = Index(p.piece_to_model.size());
        p.piece_to_model.push_back(k);
        p.piece.nodes.push_back(model_mesh.nodes[std::size_t(k)]);
      }
      p.piece.cells.connectivity.push_back(n);
    }
  }
  p.probed = probes.nodes("fluid");
  return p;
}

ProbeGather::ProbeGather(const FluidPieces& pieces, std::vector<Quantity> quantities, Value value)
    : pieces_(pieces), quantities_(std::move(quantities)), value_(std::move(value)) {
  for (const Quantity& q : quantities_) {
    offset_.push_back(per_node_);
    per_node_ += std::size_t(q.components);
  }
  values_.assign(per_node_ * pieces_.probed.size(), 0.0);
}

void ProbeGather::refresh() {
  const mpi::Communicator& ranks = *pieces_.ranks;
  owners_.resize(pieces_.probed.size());
  for (std::size_t s = 0; s < pieces_.probed.size(); ++s) {
    const auto i = std::size_t(pieces_.probed[s]);
    owners_[s] = pieces_.case_owner[i];
    if (owners_[s] != ranks.rank()) continue;
    for (std::size_t q = 0; q < quantities_.size(); ++q)
      value_(q, pieces_.case_to_model[i], values_.data() + s * per_node_ + offset_[q]);
  }
  mpi::gather_from_owners(ranks, owners_, values_, int(per_node_));
}

const double* ProbeGather::at(Index case_node) const {
  const auto it = std::lower_bound(pieces_.probed.begin(), pieces_.probed.end(), case_node);
  if (it == pieces_.probed.end() || *it != case_node)
    throw Error(fmt::format("fluid node {} is not among the probed nodes gathered from the ranks", case_node));
  return values_.data() + std::size_t(it - pieces_.probed.begin()) * per_node_;
}

std::vector<io::FieldView> ProbeGather::views() const {
  std::vector<io::FieldView> v;
  for (std::size_t q = 0; q < quantities_.size(); ++q)
    v.push_back({"fluid", quantities_[q].name, quantities_[q].components, {}, [this, q](Index i, double* out) {
                   const double* values = at(i) + offset_[q];
                   std::copy_n(values, quantities_[q].components, out);
                 }});
  return v;
}

}  // namespace shellflow::run
