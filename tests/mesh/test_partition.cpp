// Partitions of a mesh (mesh/partition.h): METIS parts, node owners, local parts with their
// ghost layer and exchange lists, local meshes with their groups, and the statistics.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "shellflow/core/error.h"
#include "shellflow/mesh/partition.h"
#include "support/box_mesh.h"

namespace shellflow::mesh {
namespace {

/// The unit cube in n^3 cubes of 6 tetrahedra; groups "inlet" (x = 0), "outlet" (x = 1),
/// "walls" (the other faces) and the cell group "fluid" (every cell); node tags 1000 + index.
Mesh partition_box(int n) {
  Mesh m = support::box_mesh({n, n, n}, Vec3(1, 1, 1), [](const Vec3& c) -> std::string {
    if (c.x() < 1e-12) return "inlet";
    if (c.x() > 1 - 1e-12) return "outlet";
    return "walls";
  });
  for (Index i = 0; i < m.num_nodes(); ++i) m.node_tags.push_back(1000 + static_cast<std::size_t>(i));
  PhysicalGroup fluid;
  fluid.name = "fluid";
  fluid.dim = 3;
  fluid.elements = m.cells;
  for (Index e = 0; e < m.num_cells(); ++e) fluid.cells.push_back(e);
  for (Index i = 0; i < m.num_nodes(); ++i) fluid.nodes.push_back(i);
  m.groups.push_back(fluid);
  return m;
}

std::array<Index, 3> sorted_key(std::span<const Index> f) {
  std::array<Index, 3> k{f[0], f[1], f[2]};
  std::sort(k.begin(), k.end());
  return k;
}

class PartitionOfABox : public ::testing::TestWithParam<int> {
 protected:
  static const Mesh& box() {
    static const Mesh m = partition_box(8);
    return m;
  }
};

TEST_P(PartitionOfABox, EveryCellInOneBalancedPartAndDeterministic) {
  const Mesh& m = box();
  const int parts = GetParam();
  const std::vector<int> part = partition_cells(m, parts);
  ASSERT_EQ(static_cast<Index>(part.size()), m.num_cells());
  std::vector<Index> count(static_cast<std::size_t>(parts), 0);
  for (const int p : part) {
    ASSERT_GE(p, 0);
    ASSERT_LT(p, parts);
    ++count[static_cast<std::size_t>(p)];
  }
  // METIS' k-way default tolerance is 3 %; contiguity may cost a little more, never 10 %
  // on a box of 3072 cells.
  const double mean = static_cast<double>(m.num_cells()) / parts;
  for (int p = 0; p < parts; ++p) {
    EXPECT_LE(std::abs(count[static_cast<std::size_t>(p)] - mean), 0.1 * mean) << "part " << p << " of " << parts;
  }
  EXPECT_EQ(partition_cells(m, parts), part);
}

TEST_P(PartitionOfABox, NodeOwnersAreThePartsOfTheLowestCells) {
  const Mesh& m = box();
  const std::vector<int> part = partition_cells(m, GetParam());
  const std::vector<int> owner = node_owners(m, part);
  ASSERT_EQ(static_cast<Index>(owner.size()), m.num_nodes());
  std::vector<Index> lowest(static_cast<std::size_t>(m.num_nodes()), m.num_cells());
  for (Index e = m.num_cells() - 1; e >= 0; --e) {
    for (const Index n : m.cells.element(e)) lowest[static_cast<std::size_t>(n)] = e;
  }
  for (Index n = 0; n < m.num_nodes(); ++n) {
    ASSERT_LT(lowest[std::size_t(n)], m.num_cells());
    EXPECT_EQ(owner[std::size_t(n)], part[std::size_t(lowest[std::size_t(n)])]) << "node " << n;
  }
}

TEST_P(PartitionOfABox, LocalPartsHoldTheGhostLayerAndMatchingExchangeLists) {
  const Mesh& m = box();
  const int parts = GetParam();
  const std::vector<int> cell_part = partition_cells(m, parts);
  const std::vector<int> owner = node_owners(m, cell_part);
  std::vector<LocalPart> local;
  for (int r = 0; r < parts; ++r) local.push_back(make_local_part(m, owner, r));

  std::vector<int> times_owned(static_cast<std::size_t>(m.num_nodes()), 0);
  for (const LocalPart& lp : local) {
    const int r = lp.rank;
    ASSERT_LE(lp.num_owned, lp.num_nodes());
    // Owned first, each block in increasing global order.
    for (Index i = 0; i < lp.num_nodes(); ++i) {
      const Index g = lp.nodes[std::size_t(i)];
      EXPECT_EQ(owner[std::size_t(g)] == r, i < lp.num_owned) << "rank " << r << " local node " << i;
      if (i > 0 && i != lp.num_owned) {
        EXPECT_LT(lp.nodes[std::size_t(i - 1)], g);
      }
      if (i < lp.num_owned) ++times_owned[std::size_t(g)];
    }
    // The cells: exactly those touching an owned node, increasing; all their nodes held.
    const std::set<Index> held(lp.nodes.begin(), lp.nodes.end());
    EXPECT_TRUE(std::is_sorted(lp.cells.begin(), lp.cells.end()));
    std::vector<Index> expected_cells;
    for (Index e = 0; e < m.num_cells(); ++e) {
      const auto c = m.cells.element(e);
      if (std::any_of(c.begin(), c.end(), [&](Index n) { return owner[std::size_t(n)] == r; })) {
        expected_cells.push_back(e);
      }
    }
    EXPECT_EQ(lp.cells, expected_cells) << "rank " << r;
    ASSERT_EQ(lp.connectivity.size(), lp.cells.size() * 4);
    std::set<Index> used;
    for (std::size_t k = 0; k < lp.cells.size(); ++k) {
      const auto c = m.cells.element(lp.cells[k]);
      for (std::size_t j = 0; j < 4; ++j) {
        const Index l = lp.connectivity[4 * k + j];
        ASSERT_GE(l, 0);
        ASSERT_LT(l, lp.num_nodes());
        EXPECT_EQ(lp.nodes[std::size_t(l)], c[j]);
        EXPECT_TRUE(held.contains(c[j]));
        used.insert(c[j]);
      }
    }
    EXPECT_EQ(used, held) << "rank " << r << " holds a node of none of its cells";
    // Neighbours by increasing rank; every ghost received exactly once, from its owner.
    std::vector<int> ghost_received(std::size_t(lp.num_nodes()), 0);
    for (std::size_t k = 0; k < lp.neighbours.size(); ++k) {
      const NeighbourLists& nb = lp.neighbours[k];
      EXPECT_NE(nb.rank, r);
      if (k > 0) {
        EXPECT_LT(lp.neighbours[k - 1].rank, nb.rank);
      }
      for (const Index l : nb.receive) {
        ASSERT_GE(l, lp.num_owned);
        EXPECT_EQ(owner[std::size_t(lp.nodes[std::size_t(l)])], nb.rank);
        ++ghost_received[std::size_t(l)];
      }
      for (const Index l : nb.send) EXPECT_LT(l, lp.num_owned);
    }
    for (Index i = lp.num_owned; i < lp.num_nodes(); ++i) EXPECT_EQ(ghost_received[std::size_t(i)], 1);
  }
  for (Index n = 0; n < m.num_nodes(); ++n) EXPECT_EQ(times_owned[std::size_t(n)], 1) << "node " << n;

  // r's receive list from s and s's send list to r: the same global nodes in the same order.
  const auto lists = [&](int r, int s) -> const NeighbourLists* {
    for (const NeighbourLists& nb : local[std::size_t(r)].neighbours) {
      if (nb.rank == s) return &nb;
    }
    return nullptr;
  };
  const auto global = [&](int r, const std::vector<Index>& l) {
    std::vector<Index> g;
    for (const Index i : l) g.push_back(local[std::size_t(r)].nodes[std::size_t(i)]);
    return g;
  };
  for (int r = 0; r < parts; ++r) {
    for (int s = 0; s < parts; ++s) {
      const NeighbourLists* rs = lists(r, s);
      const NeighbourLists* sr = lists(s, r);
      ASSERT_EQ(rs == nullptr, sr == nullptr) << r << " and " << s;
      if (rs == nullptr) continue;
      const std::vector<Index> received = global(r, rs->receive);
      EXPECT_FALSE(received.empty());
      EXPECT_TRUE(std::is_sorted(received.begin(), received.end()));
      EXPECT_EQ(received, global(s, sr->send)) << "rank " << r << " from " << s;
    }
  }

  // The statistics count what the local parts hold.
  const PartitionStats stats = partition_stats(m, cell_part, owner);
  ASSERT_EQ(static_cast<int>(stats.parts.size()), parts);
  EXPECT_EQ(stats.nodes, m.num_nodes());
  EXPECT_EQ(stats.cells, m.num_cells());
  Index ghosts = 0;
  for (int r = 0; r < parts; ++r) {
    const LocalPart& lp = local[std::size_t(r)];
    const PartStats& ps = stats.parts[std::size_t(r)];
    std::set<Index> interface;
    for (const NeighbourLists& nb : lp.neighbours) interface.insert(nb.send.begin(), nb.send.end());
    Index ghost_cells = 0;
    for (const Index e : lp.cells) ghost_cells += cell_part[std::size_t(e)] != r ? 1 : 0;
    EXPECT_EQ(ps.owned_nodes, lp.num_owned);
    EXPECT_EQ(ps.ghost_nodes, lp.num_ghosts());
    EXPECT_EQ(ps.local_cells, static_cast<Index>(lp.cells.size()));
    EXPECT_EQ(ps.ghost_cells, ghost_cells);
    EXPECT_EQ(ps.owned_cells, std::count(cell_part.begin(), cell_part.end(), r));
    EXPECT_EQ(ps.neighbours, static_cast<int>(lp.neighbours.size()));
    EXPECT_EQ(ps.interface_nodes, static_cast<Index>(interface.size()));
    EXPECT_DOUBLE_EQ(ps.halo_share, static_cast<double>(lp.num_ghosts()) / lp.num_owned);
    ghosts += lp.num_ghosts();
  }
  EXPECT_EQ(stats.ghost_nodes, ghosts);
  EXPECT_GE(stats.imbalance, 1.0);
  EXPECT_LE(stats.imbalance, 1.1);
  if (parts == 1) {
    EXPECT_EQ(stats.ghost_nodes, 0);
    EXPECT_EQ(stats.max_halo_share, 0.0);
  } else {
    EXPECT_GT(stats.mean_halo_share, 0.0);
    EXPECT_GE(stats.max_halo_share, stats.mean_halo_share);
  }
}

TEST_P(PartitionOfABox, LocalMeshesHoldTheirGroupsAndTogetherCoverEveryFacet) {
  const Mesh& m = box();
  const int parts = GetParam();
  const std::vector<int> owner = node_owners(m, partition_cells(m, parts));
  // The one cell of each boundary facet.
  std::map<std::array<Index, 3>, Index> cell_of_face;
  static constexpr int faces[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  for (Index e = 0; e < m.num_cells(); ++e) {
    const auto c = m.cells.element(e);
    for (const auto& f : faces) {
      const std::array<Index, 3> v{c[std::size_t(f[0])], c[std::size_t(f[1])], c[std::size_t(f[2])]};
      cell_of_face[sorted_key(v)] = e;
    }
  }
  std::map<std::string, std::set<std::array<Index, 3>>> covered;
  for (int r = 0; r < parts; ++r) {
    const LocalPart lp = make_local_part(m, owner, r);
    const Mesh lm = local_mesh(m, lp);
    ASSERT_EQ(lm.num_nodes(), lp.num_nodes());
    ASSERT_EQ(lm.num_cells(), static_cast<Index>(lp.cells.size()));
    for (Index i = 0; i < lm.num_nodes(); ++i) {
      const Index g = lp.nodes[std::size_t(i)];
      EXPECT_EQ(lm.nodes[std::size_t(i)], m.nodes[std::size_t(g)]);
      EXPECT_EQ(lm.node_tags[std::size_t(i)], m.node_tags[std::size_t(g)]);
    }
    const std::set<Index> local_cells(lp.cells.begin(), lp.cells.end());
    ASSERT_EQ(lm.groups.size(), m.groups.size());
    for (std::size_t k = 0; k < m.groups.size(); ++k) {
      const PhysicalGroup& g = m.groups[k];
      const PhysicalGroup& lg = lm.groups[k];
      ASSERT_EQ(lg.name, g.name);
      EXPECT_TRUE(std::is_sorted(lg.nodes.begin(), lg.nodes.end()));
      if (g.dim == 3) {
        EXPECT_EQ(static_cast<Index>(lg.cells.size()), lm.num_cells());
        EXPECT_EQ(lg.elements.connectivity, lm.cells.connectivity);
        EXPECT_EQ(static_cast<Index>(lg.nodes.size()), lm.num_nodes());
        continue;
      }
      // A facet is on rank r exactly when r holds its cell.
      std::set<std::array<Index, 3>> here;
      for (Index f = 0; f < lg.elements.size(); ++f) {
        std::vector<Index> gl;
        for (const Index l : lg.elements.element(f)) gl.push_back(lp.nodes[std::size_t(l)]);
        here.insert(sorted_key(gl));
      }
      EXPECT_EQ(static_cast<Index>(here.size()), lg.elements.size()) << "a facet twice in " << g.name;
      std::set<Index> owned_group_nodes;
      for (Index f = 0; f < g.elements.size(); ++f) {
        const auto key = sorted_key(g.elements.element(f));
        EXPECT_EQ(here.contains(key), local_cells.contains(cell_of_face.at(key)))
            << "rank " << r << " group " << g.name << " facet " << f;
        for (const Index n : key) {
          if (owner[std::size_t(n)] == r) owned_group_nodes.insert(n);
        }
      }
      covered[g.name].insert(here.begin(), here.end());
      // Node list: the nodes of the kept facets, holding every owned node of the group.
      std::set<Index> facet_nodes;
      for (const Index l : lg.elements.connectivity) facet_nodes.insert(l);
      EXPECT_EQ(std::vector<Index>(facet_nodes.begin(), facet_nodes.end()), lg.nodes);
      for (const Index n : owned_group_nodes) {
        const auto it = std::find(lp.nodes.begin(), lp.nodes.end(), n);
        ASSERT_NE(it, lp.nodes.end());
        EXPECT_TRUE(std::binary_search(lg.nodes.begin(), lg.nodes.end(), Index(it - lp.nodes.begin())));
      }
    }
  }
  for (const PhysicalGroup& g : m.groups) {
    if (g.dim == 3) continue;
    EXPECT_EQ(static_cast<Index>(covered[g.name].size()), g.elements.size()) << g.name;
  }
}

INSTANTIATE_TEST_SUITE_P(Parts, PartitionOfABox, ::testing::Values(1, 2, 3, 4, 7));

TEST(Partition, BadPartCountsAreRefused) {
  const Mesh m = partition_box(2);  // 48 cells
  for (const int parts : {0, -3, 49}) {
    try {
      (void)partition_cells(m, parts);
      ADD_FAILURE() << parts << " parts accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("the number of parts must be between 1 and 48"), std::string::npos)
          << e.what();
    }
  }
  EXPECT_EQ(partition_cells(m, 48).size(), 48u);
  const std::vector<int> short_parts(3, 0);
  EXPECT_THROW((void)node_owners(m, short_parts), InputError);
}

TEST(Partition, DisconnectedMeshesAndTrianglesArePartitioned) {
  // Two boxes side by side without a shared face: no contiguous split exists.
  Mesh two = partition_box(3);
  const Mesh b = partition_box(3);
  const Index offset = two.num_nodes();
  for (const Vec3& x : b.nodes) two.nodes.push_back(x + Vec3(2, 0, 0));
  for (const Index n : b.cells.connectivity) two.cells.connectivity.push_back(n + offset);
  two.node_tags.clear();
  two.groups.clear();
  const std::vector<int> part = partition_cells(two, 3);
  for (int p = 0; p < 3; ++p) EXPECT_GT(std::count(part.begin(), part.end(), p), 0) << p;
  EXPECT_EQ(partition_stats(two, part, node_owners(two, part)).nodes, two.num_nodes());

  // A square of 2 n^2 triangles (cells share an edge: ncommon 2).
  Mesh tri;
  tri.name = "square";
  tri.cells.type = ElementType::tri3;
  const int n = 10;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) tri.nodes.emplace_back(i, j, 0);
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const Index a = j * (n + 1) + i;
      tri.cells.connectivity.insert(tri.cells.connectivity.end(), {a, a + 1, a + n + 2, a, a + n + 2, a + n + 1});
    }
  }
  const std::vector<int> tri_part = partition_cells(tri, 4);
  std::vector<Index> count(4, 0);
  for (const int p : tri_part) ++count[std::size_t(p)];
  for (const Index c : count) EXPECT_NEAR(c, 50, 5);
  const std::vector<int> tri_owner = node_owners(tri, tri_part);
  Index owned = 0;
  for (int r = 0; r < 4; ++r) owned += make_local_part(tri, tri_owner, r).num_owned;
  EXPECT_EQ(owned, tri.num_nodes());
}

}  // namespace
}  // namespace shellflow::mesh
