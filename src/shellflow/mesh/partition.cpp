#include "shellflow/mesh/partition.h"

#include <metis.h>

#include <algorithm>
#include <cstddef>
#include <limits>
#include <utility>

#include "shellflow/core/error.h"

namespace shellflow::mesh {

namespace {

const char* metis_status_name(int status) {
  switch (status) {
    case METIS_ERROR_INPUT:
      return "METIS_ERROR_INPUT";
    case METIS_ERROR_MEMORY:
      return "METIS_ERROR_MEMORY";
    case METIS_ERROR:
      return "METIS_ERROR";
    default:
      return "an unknown METIS status";
  }
}

void check_cell_parts(const Mesh& mesh, std::span<const int> cell_part) {
  if (static_cast<Index>(cell_part.size()) != mesh.num_cells()) {
    throw_input_error("mesh '{}': {} cell parts given for {} cells", mesh.name, cell_part.size(), mesh.num_cells());
  }
  for (std::size_t c = 0; c < cell_part.size(); ++c) {
    if (cell_part[c] < 0) throw_input_error("mesh '{}': cell {} has the negative part {}", mesh.name, c, cell_part[c]);
  }
}

void check_node_owners(const Mesh& mesh, std::span<const int> node_owner) {
  if (static_cast<Index>(node_owner.size()) != mesh.num_nodes()) {
    throw_input_error("mesh '{}': {} node owners given for {} nodes", mesh.name, node_owner.size(), mesh.num_nodes());
  }
  for (std::size_t n = 0; n < node_owner.size(); ++n) {
    if (node_owner[n] < 0)
      throw_input_error("mesh '{}': node {} has the negative owner {}", mesh.name, n, node_owner[n]);
  }
}

/// Whether the cells' face-adjacency (dual) graph is connected: METIS can make contiguous
/// parts only then (it fails on a disconnected graph when asked for them).
bool dual_graph_connected(idx_t ne, idx_t nn, std::vector<idx_t>& eptr, std::vector<idx_t>& eind, idx_t ncommon) {
  idx_t numflag = 0;
  idx_t* xadj = nullptr;
  idx_t* adjncy = nullptr;
  const int status = METIS_MeshToDual(&ne, &nn, eptr.data(), eind.data(), &ncommon, &numflag, &xadj, &adjncy);
  if (status != METIS_OK) {
    throw Error(fmt::format("METIS_MeshToDual failed with {} ({})", metis_status_name(status), status));
  }
  std::vector<char> seen(static_cast<std::size_t>(ne), 0);
  std::vector<idx_t> stack{0};
  seen[0] = 1;
  idx_t reached = 1;
  while (!stack.empty()) {
    const idx_t v = stack.back();
    stack.pop_back();
    for (idx_t k = xadj[v]; k < xadj[v + 1]; ++k) {
      const idx_t w = adjncy[k];
      if (seen[static_cast<std::size_t>(w)] == 0) {
        seen[static_cast<std::size_t>(w)] = 1;
        ++reached;
        stack.push_back(w);
      }
    }
  }
  METIS_Free(xadj);
  METIS_Free(adjncy);
  return reached == ne;
}

}  // namespace

std::vector<int> partition_cells(const Mesh& mesh, int parts) {
  const Index num_cells = mesh.num_cells();
  if (parts < 1 || parts > num_cells) {
    throw_input_error("mesh '{}': cannot split {} cells into {} parts; the number of parts must be between 1 and {}",
                      mesh.name, num_cells, parts, num_cells);
  }
  std::vector<int> cell_part(static_cast<std::size_t>(num_cells), 0);
  if (parts == 1) return cell_part;

  const ElementInfo& info = element_info(mesh.cells.type);
  const int nv = info.num_vertices;
  // idx_t may be 32 or 64 bit (metis.h: IDXTYPEWIDTH): every count must fit.
  const auto total = static_cast<long long>(num_cells) * nv;
  if (total > static_cast<long long>(std::numeric_limits<idx_t>::max())) {
    throw Error(fmt::format("mesh '{}': {} cell vertices exceed METIS' index type ({} bit)", mesh.name, total,
                            static_cast<int>(8 * sizeof(idx_t))));
  }
  std::vector<idx_t> eptr(static_cast<std::size_t>(num_cells) + 1);
  std::vector<idx_t> eind(static_cast<std::size_t>(total));
  for (Index e = 0; e < num_cells; ++e) {
    const auto cell = mesh.cells.element(e);
    eptr[static_cast<std::size_t>(e)] = static_cast<idx_t>(e) * nv;
    for (int k = 0; k < nv; ++k) {
      eind[static_cast<std::size_t>(e) * static_cast<std::size_t>(nv) + static_cast<std::size_t>(k)] =
          static_cast<idx_t>(cell[static_cast<std::size_t>(k)]);
    }
  }
  eptr.back() = static_cast<idx_t>(total);

  idx_t ne = static_cast<idx_t>(num_cells);
  idx_t nn = static_cast<idx_t>(mesh.num_nodes());
  idx_t ncommon = info.dim == 3 ? 3 : info.dim == 2 ? 2 : 1;  // cells sharing a face (an edge, a point)
  idx_t nparts = static_cast<idx_t>(parts);
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_PTYPE] = METIS_PTYPE_KWAY;
  options[METIS_OPTION_OBJTYPE] = METIS_OBJTYPE_CUT;
  options[METIS_OPTION_SEED] = 1;
  options[METIS_OPTION_NUMBERING] = 0;
  options[METIS_OPTION_CONTIG] = dual_graph_connected(ne, nn, eptr, eind, ncommon) ? 1 : 0;

  idx_t objval = 0;
  std::vector<idx_t> epart(static_cast<std::size_t>(num_cells));
  std::vector<idx_t> npart(static_cast<std::size_t>(mesh.num_nodes()));
  const int status = METIS_PartMeshDual(&ne, &nn, eptr.data(), eind.data(), nullptr, nullptr, &ncommon, &nparts,
                                        nullptr, options, &objval, epart.data(), npart.data());
  if (status != METIS_OK) {
    throw Error(fmt::format("mesh '{}': METIS_PartMeshDual failed with {} ({}) for {} parts of {} cells", mesh.name,
                            metis_status_name(status), status, parts, num_cells));
  }
  for (std::size_t e = 0; e < epart.size(); ++e) cell_part[e] = static_cast<int>(epart[e]);
  return cell_part;
}

std::vector<int> node_owners(const Mesh& mesh, std::span<const int> cell_part) {
  check_cell_parts(mesh, cell_part);
  std::vector<int> owner(static_cast<std::size_t>(mesh.num_nodes()), -1);
  for (Index e = 0; e < mesh.num_cells(); ++e) {
    for (const Index n : mesh.cells.element(e)) {
      int& o = owner[static_cast<std::size_t>(n)];
      if (o < 0) o = cell_part[static_cast<std::size_t>(e)];
    }
  }
  for (int& o : owner) {
    if (o < 0) o = 0;
  }
  return owner;
}

LocalPart make_local_part(const Mesh& mesh, std::span<const int> node_owner, int rank) {
  check_node_owners(mesh, node_owner);
  if (rank < 0) throw_input_error("mesh '{}': negative rank {}", mesh.name, rank);
  LocalPart part;
  part.rank = rank;
  const auto owner_of = [&](Index n) { return node_owner[static_cast<std::size_t>(n)]; };

  // The cells with an owned node; the nodes they hold; per neighbour, the pairs it shares.
  std::vector<char> held(static_cast<std::size_t>(mesh.num_nodes()), 0);
  std::vector<std::pair<int, Index>> sends;  // (neighbour, global node owned here)
  for (Index e = 0; e < mesh.num_cells(); ++e) {
    const auto cell = mesh.cells.element(e);
    bool mine = false;
    for (const Index n : cell) mine = mine || owner_of(n) == rank;
    if (!mine) continue;
    part.cells.push_back(e);
    for (const Index n : cell) held[static_cast<std::size_t>(n)] = 1;
    // Every other rank owning a node of this cell holds the cell, so it holds this rank's
    // nodes of the cell as ghosts.
    for (const Index other : cell) {
      const int s = owner_of(other);
      if (s == rank) continue;
      for (const Index n : cell) {
        if (owner_of(n) == rank) sends.emplace_back(s, n);
      }
    }
  }
  // Owned nodes: also one in no cell (none from node_owners but those of no cell, owned by 0).
  for (Index n = 0; n < mesh.num_nodes(); ++n) {
    if (owner_of(n) == rank) part.nodes.push_back(n);
  }
  part.num_owned = static_cast<Index>(part.nodes.size());
  for (Index n = 0; n < mesh.num_nodes(); ++n) {
    if (held[static_cast<std::size_t>(n)] != 0 && owner_of(n) != rank) part.nodes.push_back(n);
  }

  std::vector<Index> local_of(static_cast<std::size_t>(mesh.num_nodes()), -1);
  for (Index i = 0; i < part.num_nodes(); ++i) local_of[static_cast<std::size_t>(part.nodes[std::size_t(i)])] = i;
  const int npe = mesh.cells.nodes_per_element();
  part.connectivity.reserve(part.cells.size() * static_cast<std::size_t>(npe));
  for (const Index e : part.cells) {
    for (const Index n : mesh.cells.element(e)) part.connectivity.push_back(local_of[static_cast<std::size_t>(n)]);
  }

  // Exchange lists: both in increasing global index (local order of owned and of ghost nodes
  // is increasing global order, so sorting local indices within one list does it).
  std::sort(sends.begin(), sends.end());
  sends.erase(std::unique(sends.begin(), sends.end()), sends.end());
  std::vector<std::pair<int, Index>> receives;  // (owner, ghost node)
  for (Index i = part.num_owned; i < part.num_nodes(); ++i) {
    const Index g = part.nodes[static_cast<std::size_t>(i)];
    receives.emplace_back(owner_of(g), g);
  }
  std::sort(receives.begin(), receives.end());
  std::vector<int> ranks;
  for (const auto& [s, n] : sends) ranks.push_back(s);
  for (const auto& [s, n] : receives) ranks.push_back(s);
  std::sort(ranks.begin(), ranks.end());
  ranks.erase(std::unique(ranks.begin(), ranks.end()), ranks.end());
  std::size_t a = 0, b = 0;
  for (const int s : ranks) {
    NeighbourLists lists;
    lists.rank = s;
    for (; a < sends.size() && sends[a].first == s; ++a) {
      lists.send.push_back(local_of[static_cast<std::size_t>(sends[a].second)]);
    }
    for (; b < receives.size() && receives[b].first == s; ++b) {
      lists.receive.push_back(local_of[static_cast<std::size_t>(receives[b].second)]);
    }
    part.neighbours.push_back(std::move(lists));
  }
  return part;
}

Mesh local_mesh(const Mesh& mesh, const LocalPart& part) {
  Mesh out;
  out.name = mesh.name;
  out.source = mesh.source;
  std::vector<Index> local_of(static_cast<std::size_t>(mesh.num_nodes()), -1);
  for (Index i = 0; i < part.num_nodes(); ++i) {
    const Index g = part.nodes[static_cast<std::size_t>(i)];
    local_of[static_cast<std::size_t>(g)] = i;
    out.nodes.push_back(mesh.nodes[static_cast<std::size_t>(g)]);
    if (!mesh.node_tags.empty()) out.node_tags.push_back(mesh.node_tags[static_cast<std::size_t>(g)]);
  }
  out.cells.type = mesh.cells.type;
  out.cells.connectivity = part.connectivity;
  std::vector<Index> local_cell_of(static_cast<std::size_t>(mesh.num_cells()), -1);
  for (std::size_t c = 0; c < part.cells.size(); ++c) {
    local_cell_of[static_cast<std::size_t>(part.cells[c])] = static_cast<Index>(c);
  }
  // Local node -> local cells (compressed rows), to find the cell of a facet.
  std::vector<Index> first(static_cast<std::size_t>(out.num_nodes()) + 1, 0);
  for (const Index n : out.cells.connectivity) ++first[static_cast<std::size_t>(n) + 1];
  for (std::size_t i = 1; i < first.size(); ++i) first[i] += first[i - 1];
  std::vector<Index> cells_of(out.cells.connectivity.size());
  {
    std::vector<Index> next(first.begin(), first.end() - 1);
    for (Index c = 0; c < out.num_cells(); ++c) {
      for (const Index n : out.cells.element(c)) cells_of[static_cast<std::size_t>(next[std::size_t(n)]++)] = c;
    }
  }
  const auto in_one_local_cell = [&](std::span<const Index> vertices) {
    const auto v0 = static_cast<std::size_t>(vertices[0]);
    for (Index k = first[v0]; k < first[v0 + 1]; ++k) {
      const auto cell = out.cells.element(cells_of[static_cast<std::size_t>(k)]);
      bool all = true;
      for (const Index v : vertices) all = all && std::find(cell.begin(), cell.end(), v) != cell.end();
      if (all) return true;
    }
    return false;
  };

  for (const PhysicalGroup& g : mesh.groups) {
    PhysicalGroup lg;
    lg.name = g.name;
    lg.dim = g.dim;
    lg.tag = g.tag;
    lg.elements.type = g.elements.type;
    if (g.dim == mesh.dim()) {
      for (const Index c : g.cells) {
        if (local_cell_of[static_cast<std::size_t>(c)] >= 0) lg.cells.push_back(local_cell_of[std::size_t(c)]);
      }
      std::sort(lg.cells.begin(), lg.cells.end());
      if (!g.elements.connectivity.empty()) {
        lg.elements.type = mesh.cells.type;
        for (const Index c : lg.cells) {
          const auto cell = out.cells.element(c);
          lg.elements.connectivity.insert(lg.elements.connectivity.end(), cell.begin(), cell.end());
        }
      }
    } else if (!g.elements.connectivity.empty()) {
      const auto nv = static_cast<std::size_t>(element_info(g.elements.type).num_vertices);
      std::vector<Index> local(static_cast<std::size_t>(g.elements.nodes_per_element()));
      for (Index f = 0; f < g.elements.size(); ++f) {
        const auto element = g.elements.element(f);
        bool all_local = true;
        for (std::size_t k = 0; k < element.size(); ++k) {
          local[k] = local_of[static_cast<std::size_t>(element[k])];
          all_local = all_local && local[k] >= 0;
        }
        if (!all_local || !in_one_local_cell(std::span<const Index>(local.data(), nv))) continue;
        lg.elements.connectivity.insert(lg.elements.connectivity.end(), local.begin(), local.end());
      }
    }
    if (g.elements.connectivity.empty()) {
      for (const Index n : g.nodes) {
        if (local_of[static_cast<std::size_t>(n)] >= 0) lg.nodes.push_back(local_of[static_cast<std::size_t>(n)]);
      }
    } else {
      lg.nodes = lg.elements.connectivity;
    }
    std::sort(lg.nodes.begin(), lg.nodes.end());
    lg.nodes.erase(std::unique(lg.nodes.begin(), lg.nodes.end()), lg.nodes.end());
    out.groups.push_back(std::move(lg));
  }
  return out;
}

PartitionStats partition_stats(const Mesh& mesh, std::span<const int> cell_part, std::span<const int> node_owner) {
  check_cell_parts(mesh, cell_part);
  check_node_owners(mesh, node_owner);
  int nparts = 1;
  for (const int p : cell_part) nparts = std::max(nparts, p + 1);
  for (const int p : node_owner) nparts = std::max(nparts, p + 1);
  PartitionStats stats;
  stats.parts.resize(static_cast<std::size_t>(nparts));
  const auto at = [&](int p) -> PartStats& { return stats.parts[static_cast<std::size_t>(p)]; };
  for (const int p : node_owner) ++at(p).owned_nodes;
  for (const int p : cell_part) ++at(p).owned_cells;

  // A cell is local to every rank owning one of its nodes; on a cell of several owners each
  // holds the others' nodes as ghosts, sends its own and neighbours them.
  std::vector<std::pair<int, Index>> ghosts, interface;
  std::vector<std::pair<int, int>> neighbours;
  std::vector<int> owners;
  for (Index e = 0; e < mesh.num_cells(); ++e) {
    const auto cell = mesh.cells.element(e);
    owners.clear();
    for (const Index n : cell) owners.push_back(node_owner[static_cast<std::size_t>(n)]);
    std::sort(owners.begin(), owners.end());
    owners.erase(std::unique(owners.begin(), owners.end()), owners.end());
    for (const int r : owners) {
      ++at(r).local_cells;
      if (cell_part[static_cast<std::size_t>(e)] != r) ++at(r).ghost_cells;
      if (owners.size() == 1) continue;
      for (const int s : owners) {
        if (s != r) neighbours.emplace_back(r, s);
      }
      for (const Index n : cell) {
        (node_owner[static_cast<std::size_t>(n)] == r ? interface : ghosts).emplace_back(r, n);
      }
    }
  }
  const auto count_unique = [&](auto& pairs, auto field) {
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    for (const auto& pr : pairs) ++(at(pr.first).*field);
  };
  count_unique(ghosts, &PartStats::ghost_nodes);
  count_unique(interface, &PartStats::interface_nodes);
  count_unique(neighbours, &PartStats::neighbours);

  Index max_cells = 0, max_local = 0, local_total = 0;
  for (PartStats& p : stats.parts) {
    p.halo_share = p.owned_nodes > 0 ? static_cast<double>(p.ghost_nodes) / p.owned_nodes : p.ghost_nodes;
    stats.nodes += p.owned_nodes;
    stats.cells += p.owned_cells;
    stats.ghost_nodes += p.ghost_nodes;
    stats.ghost_cells += p.ghost_cells;
    stats.interface_nodes += p.interface_nodes;
    max_cells = std::max(max_cells, p.owned_cells);
    max_local = std::max(max_local, p.local_cells);
    local_total += p.local_cells;
    stats.max_halo_share = std::max(stats.max_halo_share, p.halo_share);
    stats.mean_halo_share += p.halo_share / nparts;
  }
  if (stats.cells > 0) stats.imbalance = static_cast<double>(max_cells) * nparts / stats.cells;
  if (local_total > 0) stats.work_imbalance = static_cast<double>(max_local) * nparts / local_total;
  return stats;
}

}  // namespace shellflow::mesh
