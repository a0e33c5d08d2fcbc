#include "shellflow/fluid/ordering.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstdlib>
#include <numeric>
#include <queue>

#include "shellflow/core/error.h"

namespace shellflow::fluid {
namespace {

/// Compressed node-to-node adjacency (without self loops).
struct Adjacency {
  std::vector<Index> offsets;
  std::vector<Index> neighbours;
  Index degree(Index a) const { return offsets[std::size_t(a) + 1] - offsets[std::size_t(a)]; }
};

Adjacency node_adjacency(std::span<const Index> conn, int npc, Index num_nodes) {
  const std::size_t nc = conn.size() / std::size_t(npc);
  std::vector<std::vector<Index>> lists(static_cast<std::size_t>(num_nodes));
  for (std::size_t c = 0; c < nc; ++c)
    for (int i = 0; i < npc; ++i)
      for (int j = 0; j < npc; ++j)
        if (i != j) lists[std::size_t(conn[c * npc + i])].push_back(conn[c * npc + j]);
  Adjacency adj;
  adj.offsets.assign(std::size_t(num_nodes) + 1, 0);
  for (Index a = 0; a < num_nodes; ++a) {
    auto& l = lists[std::size_t(a)];
    std::sort(l.begin(), l.end());
    l.erase(std::unique(l.begin(), l.end()), l.end());
    adj.offsets[std::size_t(a) + 1] = adj.offsets[std::size_t(a)] + Index(l.size());
  }
  adj.neighbours.reserve(std::size_t(adj.offsets.back()));
  for (auto& l : lists) adj.neighbours.insert(adj.neighbours.end(), l.begin(), l.end());
  return adj;
}

/// Breadth-first level structure from `root`; returns the visit order, marks `level`.
std::vector<Index> bfs(const Adjacency& adj, Index root, std::vector<Index>& level, bool sort_by_degree) {
  std::vector<Index> order{root};
  level[std::size_t(root)] = 0;
  std::vector<Index> next;
  for (std::size_t head = 0; head < order.size(); ++head) {
    const Index a = order[head];
    next.clear();
    for (Index k = adj.offsets[std::size_t(a)]; k < adj.offsets[std::size_t(a) + 1]; ++k) {
      const Index b = adj.neighbours[std::size_t(k)];
      if (level[std::size_t(b)] < 0) {
        level[std::size_t(b)] = level[std::size_t(a)] + 1;
        next.push_back(b);
      }
    }
    if (sort_by_degree)
      std::stable_sort(next.begin(), next.end(), [&](Index p, Index q) { return adj.degree(p) < adj.degree(q); });
    order.insert(order.end(), next.begin(), next.end());
  }
  return order;
}

}  // namespace

std::vector<Index> reverse_cuthill_mckee(std::span<const Index> conn, int npc, Index num_nodes) {
  const Adjacency adj = node_adjacency(conn, npc, num_nodes);
  std::vector<Index> cm;  // Cuthill–McKee order (old indices)
  cm.reserve(std::size_t(num_nodes));
  std::vector<Index> visited(static_cast<std::size_t>(num_nodes), -1);
  std::vector<Index> level(static_cast<std::size_t>(num_nodes), -1);
  std::vector<Index> by_degree(static_cast<std::size_t>(num_nodes));
  std::iota(by_degree.begin(), by_degree.end(), 0);
  std::stable_sort(by_degree.begin(), by_degree.end(), [&](Index p, Index q) { return adj.degree(p) < adj.degree(q); });
  for (const Index start : by_degree) {
    if (visited[std::size_t(start)] >= 0 || adj.degree(start) == 0) continue;
    // Pseudo-peripheral root: hop to a minimum-degree node of the last level while the
    // eccentricity grows (George–Liu, a few iterations suffice).
    Index root = start;
    Index depth = -1;
    for (int iter = 0; iter < 8; ++iter) {
      const auto comp = bfs(adj, root, level, false);
      const Index d = level[std::size_t(comp.back())];
      Index candidate = comp.back();
      for (const Index a : comp)
        if (level[std::size_t(a)] == d && adj.degree(a) < adj.degree(candidate)) candidate = a;
      for (const Index a : comp) level[std::size_t(a)] = -1;
      if (d <= depth) break;
      depth = d;
      root = candidate;
    }
    const auto comp = bfs(adj, root, level, true);
    for (const Index a : comp) visited[std::size_t(a)] = 1;
    cm.insert(cm.end(), comp.begin(), comp.end());
  }
  std::vector<Index> new_index(static_cast<std::size_t>(num_nodes), -1);
  Index next = 0;
  for (auto it = cm.rbegin(); it != cm.rend(); ++it) new_index[std::size_t(*it)] = next++;
  for (auto& v : new_index)
    if (v < 0) v = next++;  // isolated nodes
  return new_index;
}

Index node_bandwidth(std::span<const Index> conn, int npc) {
  Index bw = 0;
  for (std::size_t c = 0; c < conn.size() / std::size_t(npc); ++c) {
    const auto [lo, hi] = std::minmax_element(conn.begin() + long(c * npc), conn.begin() + long((c + 1) * npc));
    bw = std::max(bw, *hi - *lo);
  }
  return bw;
}

std::vector<Index> renumber_for_locality(mesh::Mesh& m) {
  const int npc = m.cells.nodes_per_element();
  const auto new_index = reverse_cuthill_mckee(m.cells.connectivity, npc, m.num_nodes());
  auto remap = [&](std::vector<Index>& v) {
    for (auto& a : v) a = new_index[std::size_t(a)];
  };
  std::vector<Vec3> nodes(m.nodes.size());
  for (std::size_t a = 0; a < m.nodes.size(); ++a) nodes[std::size_t(new_index[a])] = m.nodes[a];
  m.nodes = std::move(nodes);
  if (m.node_tags.size() == new_index.size()) {
    std::vector<std::size_t> tags(m.node_tags.size());
    for (std::size_t a = 0; a < tags.size(); ++a) tags[std::size_t(new_index[a])] = m.node_tags[a];
    m.node_tags = std::move(tags);
  }
  remap(m.cells.connectivity);
  // Cells sorted by their smallest node: consecutive cells share nodes.
  const Index nc = m.num_cells();
  std::vector<Index> cell_order(static_cast<std::size_t>(nc));
  std::iota(cell_order.begin(), cell_order.end(), 0);
  std::vector<Index> key(static_cast<std::size_t>(nc));
  for (Index c = 0; c < nc; ++c) {
    const auto cell = m.cells.element(c);
    key[std::size_t(c)] = *std::min_element(cell.begin(), cell.end());
  }
  std::stable_sort(cell_order.begin(), cell_order.end(),
                   [&](Index p, Index q) { return key[std::size_t(p)] < key[std::size_t(q)]; });
  std::vector<Index> conn;
  conn.reserve(m.cells.connectivity.size());
  std::vector<Index> new_cell(static_cast<std::size_t>(nc));
  for (Index k = 0; k < nc; ++k) {
    const auto cell = m.cells.element(cell_order[std::size_t(k)]);
    conn.insert(conn.end(), cell.begin(), cell.end());
    new_cell[std::size_t(cell_order[std::size_t(k)])] = k;
  }
  m.cells.connectivity = std::move(conn);
  for (auto& g : m.groups) {
    remap(g.elements.connectivity);
    remap(g.nodes);
    std::sort(g.nodes.begin(), g.nodes.end());
    for (auto& c : g.cells) c = new_cell[std::size_t(c)];
  }
  return new_index;
}

Index default_block_size(Index num_cells) { return std::clamp<Index>(num_cells / 64, 256, 8192); }

CellColouring colour_cells(std::span<const Index> conn, int npc, Index num_nodes, Index block_size) {
  const auto nc = static_cast<Index>(conn.size() / std::size_t(npc));
  block_size = std::max<Index>(1, block_size);
  const Index nb = (nc + block_size - 1) / block_size;
  // Up to 128 colours: two 64-bit masks of the colours already used at each node.
  std::vector<std::array<std::uint64_t, 2>> used(static_cast<std::size_t>(num_nodes), {0, 0});
  std::vector<int> colour(static_cast<std::size_t>(nb));
  int num_colours = 0;
  for (Index b = 0; b < nb; ++b) {
    const std::size_t begin = std::size_t(b) * std::size_t(block_size) * std::size_t(npc);
    const std::size_t end = std::min<std::size_t>(conn.size(), begin + std::size_t(block_size) * std::size_t(npc));
    std::array<std::uint64_t, 2> mask{0, 0};
    for (std::size_t i = begin; i < end; ++i) {
      const auto& u = used[std::size_t(conn[i])];
      mask[0] |= u[0];
      mask[1] |= u[1];
    }
    int k = 0;
    if (~mask[0] != 0) {
      k = std::countr_one(mask[0]);
    } else if (~mask[1] != 0) {
      k = 64 + std::countr_one(mask[1]);
    } else {
      throw SolverError(
          "fluid mesh needs more than 128 element colours: a node has too "
          "many elements; check the mesh quality");
    }
    colour[std::size_t(b)] = k;
    num_colours = std::max(num_colours, k + 1);
    for (std::size_t i = begin; i < end; ++i)
      used[std::size_t(conn[i])][std::size_t(k / 64)] |= std::uint64_t{1} << (k % 64);
  }
  CellColouring out;
  out.colour_offsets.assign(std::size_t(num_colours) + 1, 0);
  for (const int k : colour) ++out.colour_offsets[std::size_t(k) + 1];
  for (int k = 0; k < num_colours; ++k) out.colour_offsets[std::size_t(k) + 1] += out.colour_offsets[std::size_t(k)];
  std::vector<Index> blocks(static_cast<std::size_t>(nb));  // block ids in colour order
  auto fill = out.colour_offsets;
  for (Index b = 0; b < nb; ++b) blocks[std::size_t(fill[std::size_t(colour[std::size_t(b)])]++)] = b;
  out.order.reserve(std::size_t(nc));
  out.block_offsets.assign(1, 0);
  for (const Index b : blocks) {
    for (Index c = b * block_size; c < std::min(nc, (b + 1) * block_size); ++c) out.order.push_back(c);
    out.block_offsets.push_back(Index(out.order.size()));
  }
  return out;
}

CellColouring restrict_colouring(const CellColouring& whole, std::span<const Index> cells) {
  const auto n = static_cast<Index>(whole.order.size());
  std::vector<Index> local(std::size_t(n), -1);
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (cells[i] < 0 || cells[i] >= n || (i > 0 && cells[i] <= cells[i - 1]))
      throw InputError(
          fmt::format("restrict_colouring: cell {} ({}) of the rank is outside the {} cells of the mesh "
                      "or out of order",
                      i, cells[i], n));
    local[std::size_t(cells[i])] = Index(i);
  }
  CellColouring out;
  out.order.reserve(cells.size());
  out.block_offsets.assign(1, 0);
  out.colour_offsets.assign(1, 0);
  for (int c = 0; c < whole.num_colours(); ++c) {
    for (Index b = whole.colour_offsets[std::size_t(c)]; b < whole.colour_offsets[std::size_t(c) + 1]; ++b) {
      for (Index k = whole.block_offsets[std::size_t(b)]; k < whole.block_offsets[std::size_t(b) + 1]; ++k)
        if (const Index l = local[std::size_t(whole.order[std::size_t(k)])]; l >= 0) out.order.push_back(l);
      if (Index(out.order.size()) > out.block_offsets.back()) out.block_offsets.push_back(Index(out.order.size()));
    }
    out.colour_offsets.push_back(out.num_blocks());
  }
  return out;
}

}  // namespace shellflow::fluid
