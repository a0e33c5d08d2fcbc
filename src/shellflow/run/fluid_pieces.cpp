#include "shellflow/run/fluid_pieces.h"

#include <fmt/format.h>

#include <algorithm>

#include "shellflow/core/error.h"

namespace shellflow::run {

FluidPieces make_fluid_pieces(const setup::Flow& flow, const dist::Communicator& ranks, const io::ProbeSet& probes) {
  const setup::FlowPart& part = *flow.part;
  const mesh::LocalPart& local = part.local;
  const mesh::Mesh& model_mesh = flow.model->mesh();
  FluidPieces p;
  p.ranks = &ranks;
  // Whole node -> model node.
  std::vector<Index> model_of(part.whole.nodes.size(), -1);
  for (std::size_t i = 0; i < local.nodes.size(); ++i) model_of[std::size_t(local.nodes[i])] = Index(i);
  p.case_to_model.resize(flow.new_index.size());
  p.case_owner.resize(flow.new_index.size());
  for (std::size_t i = 0; i < flow.new_index.size(); ++i) {
    p.case_to_model[i] = model_of[std::size_t(flow.new_index[i])];
    p.case_owner[i] = part.node_owner[std::size_t(flow.new_index[i])];
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
  const dist::Communicator& ranks = *pieces_.ranks;
  std::vector<double> mine;
  for (const Index i : pieces_.probed) {
    if (pieces_.case_owner[std::size_t(i)] != ranks.rank()) continue;
    const std::size_t at = mine.size();
    mine.resize(at + per_node_);
    for (std::size_t q = 0; q < quantities_.size(); ++q)
      value_(q, pieces_.case_to_model[std::size_t(i)], mine.data() + at + offset_[q]);
  }
  const std::vector<double> all = ranks.all_gather(mine);
  // Rank r's values start after those of the ranks before it; each rank's come in probed order.
  std::vector<std::size_t> next(std::size_t(ranks.size()) + 1, 0);
  for (const Index i : pieces_.probed) next[std::size_t(pieces_.case_owner[std::size_t(i)]) + 1] += per_node_;
  for (std::size_t r = 1; r < next.size(); ++r) next[r] += next[r - 1];
  if (next.back() != all.size())
    throw Error(
        fmt::format("probe values of the fluid: {} gathered from the ranks, {} expected", all.size(), next.back()));
  for (std::size_t s = 0; s < pieces_.probed.size(); ++s) {
    std::size_t& from = next[std::size_t(pieces_.case_owner[std::size_t(pieces_.probed[s])])];
    std::copy_n(all.begin() + std::ptrdiff_t(from), per_node_, values_.begin() + std::ptrdiff_t(s * per_node_));
    from += per_node_;
  }
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
