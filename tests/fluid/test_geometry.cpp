// Per-tetrahedron geometry, lumped mass, RCM renumbering and element colouring.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <numeric>
#include <random>
#include <set>

#include "fluid_test_util.h"
#include "shellflow/core/error.h"
#include "shellflow/fluid/geometry.h"
#include "shellflow/fluid/ordering.h"
#include "support/box_mesh.h"

using namespace shellflow;
using namespace shellflow::fluid;

namespace {

/// The mesh with its nodes renumbered by a random permutation (a worst case for locality).
mesh::Mesh shuffled(mesh::Mesh m, unsigned seed) {
  std::vector<Index> perm(m.nodes.size());
  std::iota(perm.begin(), perm.end(), 0);
  std::shuffle(perm.begin(), perm.end(), std::mt19937(seed));
  std::vector<Vec3> nodes(m.nodes.size());
  for (std::size_t a = 0; a < perm.size(); ++a) nodes[std::size_t(perm[a])] = m.nodes[a];
  m.nodes = nodes;
  for (auto& a : m.cells.connectivity) a = perm[std::size_t(a)];
  for (auto& g : m.groups) {
    for (auto& a : g.elements.connectivity) a = perm[std::size_t(a)];
    for (auto& a : g.nodes) a = perm[std::size_t(a)];
    std::sort(g.nodes.begin(), g.nodes.end());
  }
  m.node_tags.clear();
  return m;
}

double total_volume(const mesh::Mesh& m) {
  TetGeometry g;
  compute_geometry(m.nodes, m.cells.connectivity, g);
  return std::accumulate(g.volume.begin(), g.volume.end(), 0.0);
}

}  // namespace

TEST(TetGeometry, ReferenceTetrahedronHasKnownVolumeGradientsAndSize) {
  const std::vector<Vec3> x = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const std::vector<Index> tet = {0, 1, 2, 3};
  TetGeometry g;
  compute_geometry(x, tet, g);
  EXPECT_DOUBLE_EQ(g.volume[0], 1.0 / 6.0);
  const double expected[12] = {-1, -1, -1, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  for (int i = 0; i < 12; ++i) EXPECT_NEAR(g.grad[0][std::size_t(i)], expected[i], 1e-15);
  // Smallest altitude: from the origin to the face x + y + z = 1.
  EXPECT_NEAR(g.size[0], 1.0 / std::sqrt(3.0), 1e-15);
  for (double m : g.lumped_mass) EXPECT_DOUBLE_EQ(m, 1.0 / 24.0);
}

TEST(TetGeometry, GradientsReproduceLinearFieldsAndMassSumsToVolume) {
  const auto mesh = test_support::case_mesh("tube_nx100.geo");
  TetGeometry g;
  compute_geometry(mesh.nodes, mesh.cells.connectivity, g);
  const Vec3 grad(0.7, -1.3, 2.1);
  for (Index e = 0; e < mesh.num_cells(); ++e) {
    Vec3 sum = Vec3::Zero();
    for (int a = 0; a < 4; ++a) {
      const Vec3& xa = mesh.nodes[std::size_t(mesh.cells.element(e)[std::size_t(a)])];
      for (int j = 0; j < 3; ++j) sum[j] += grad.dot(xa) * g.grad[std::size_t(e)][std::size_t(3 * a + j)];
    }
    ASSERT_LT((sum - grad).norm(), 1e-9) << "element " << e;
  }
  const double mass = std::accumulate(g.lumped_mass.begin(), g.lumped_mass.end(), 0.0);
  EXPECT_NEAR(mass, 1.0 * 0.02 * 0.02, 1e-15);
  EXPECT_EQ(mesh.num_cells(), 600);
}

TEST(TetGeometry, InvertedElementThrowsSolverErrorNamingIt) {
  std::vector<Vec3> x = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  x[3].z() = -0.1;
  TetGeometry g;
  try {
    compute_geometry(x, std::vector<Index>{0, 1, 2, 3}, g);
    FAIL() << "no error";
  } catch (const SolverError& e) {
    EXPECT_NE(std::string(e.what()).find("element 0"), std::string::npos) << e.what();
  }
}

TEST(Ordering, ReverseCuthillMcKeeShrinksTheBandwidthOfAShuffledMesh) {
  const auto original = test_support::case_mesh("unit_cube.geo");
  auto m = shuffled(original, 7);
  const Index before = node_bandwidth(m.cells.connectivity, 4);
  const double volume = total_volume(m);
  const auto new_index = renumber_for_locality(m);
  const Index after = node_bandwidth(m.cells.connectivity, 4);
  std::printf("bandwidth: shuffled %d, RCM %d (nodes %d)\n", before, after, m.num_nodes());
  EXPECT_LT(after * 5, before);
  EXPECT_LT(after, 3 * 11 * 11);                // a structured 11^3-node cube has bandwidth ~ 11^2
  EXPECT_NEAR(total_volume(m), volume, 1e-13);  // cells keep their orientation
  // A permutation; group node lists follow the nodes.
  std::set<Index> image(new_index.begin(), new_index.end());
  EXPECT_EQ(image.size(), new_index.size());
  const auto& group = m.group("boundary");
  for (const Index a : group.nodes) {
    const Vec3& x = m.nodes[std::size_t(a)];
    const double dist = std::min({x.x(), x.y(), x.z(), 1 - x.x(), 1 - x.y(), 1 - x.z()});
    ASSERT_LT(dist, 1e-12);
  }
}

TEST(Ordering, NoTwoBlocksOfOneColourShareANode) {
  const auto m = test_support::case_mesh("unit_cube.geo");
  for (const Index block_size : {1, 97, 400}) {
    const auto colours = colour_cells(m.cells.connectivity, 4, m.num_nodes(), block_size);
    EXPECT_EQ(colours.order.size(), std::size_t(m.num_cells()));
    std::set<Index> all(colours.order.begin(), colours.order.end());
    EXPECT_EQ(all.size(), colours.order.size());
    for (int c = 0; c < colours.num_colours(); ++c) {
      std::map<Index, Index> owner;  // node -> block of this colour
      for (Index b = colours.colour_offsets[std::size_t(c)]; b < colours.colour_offsets[std::size_t(c) + 1]; ++b)
        for (Index k = colours.block_offsets[std::size_t(b)]; k < colours.block_offsets[std::size_t(b) + 1]; ++k) {
          for (const Index a : m.cells.element(colours.order[std::size_t(k)])) {
            const auto [it, fresh] = owner.emplace(a, b);
            ASSERT_TRUE(fresh || it->second == b) << "colour " << c << " node " << a;
          }
        }
    }
    std::printf("block size %d: %d colours, %d blocks for %d tets\n", block_size, colours.num_colours(),
                colours.num_blocks(), m.num_cells());
    if (block_size == 1) {
      EXPECT_LE(colours.num_colours(), 40);
    }
  }
}

// A rank's colouring (restrict_colouring) keeps the whole colouring's order: its cells, mapped
// back to the whole mesh, come in the whole order; each local block lies in one whole block and
// colour; and a bad cell list is refused.
TEST(Ordering, RestrictedColouringKeepsTheWholeOrderOfTheRanksCells) {
  const auto m = test_support::case_mesh("unit_cube.geo");
  const auto whole = colour_cells(m.cells.connectivity, 4, m.num_nodes(), 97);
  std::vector<Index> block_of(std::size_t(m.num_cells())), colour_of(std::size_t(m.num_cells())),
      position(std::size_t(m.num_cells()));
  for (int c = 0; c < whole.num_colours(); ++c)
    for (Index b = whole.colour_offsets[std::size_t(c)]; b < whole.colour_offsets[std::size_t(c) + 1]; ++b)
      for (Index k = whole.block_offsets[std::size_t(b)]; k < whole.block_offsets[std::size_t(b) + 1]; ++k) {
        block_of[std::size_t(whole.order[std::size_t(k)])] = b;
        colour_of[std::size_t(whole.order[std::size_t(k)])] = c;
        position[std::size_t(whole.order[std::size_t(k)])] = k;
      }
  std::vector<Index> cells;  // every third cell and a run of consecutive ones
  for (Index c = 0; c < m.num_cells(); ++c)
    if (c % 3 == 0 || (c > m.num_cells() / 2 && c < m.num_cells() / 2 + 50)) cells.push_back(c);
  const auto local = restrict_colouring(whole, cells);
  ASSERT_EQ(local.order.size(), cells.size());
  EXPECT_EQ(local.num_colours(), whole.num_colours());
  for (std::size_t k = 1; k < local.order.size(); ++k)
    EXPECT_LT(position[std::size_t(cells[std::size_t(local.order[k - 1])])],
              position[std::size_t(cells[std::size_t(local.order[k])])]);
  for (int c = 0; c < local.num_colours(); ++c)
    for (Index b = local.colour_offsets[std::size_t(c)]; b < local.colour_offsets[std::size_t(c) + 1]; ++b) {
      const Index first = local.block_offsets[std::size_t(b)];
      ASSERT_LT(first, local.block_offsets[std::size_t(b) + 1]) << "empty block " << b;
      const Index cell = cells[std::size_t(local.order[std::size_t(first)])];
      for (Index k = first; k < local.block_offsets[std::size_t(b) + 1]; ++k) {
        const Index ck = cells[std::size_t(local.order[std::size_t(k)])];
        EXPECT_EQ(block_of[std::size_t(ck)], block_of[std::size_t(cell)]);
        EXPECT_EQ(colour_of[std::size_t(ck)], c);
      }
    }
  EXPECT_THROW(restrict_colouring(whole, std::vector<Index>{3, 2}), InputError);
  EXPECT_THROW(restrict_colouring(whole, std::vector<Index>{m.num_cells()}), InputError);
}

// The lumped mass scattered colour by colour in parallel (the moving-mesh step's path) has
// the bits of the serial sum, on a mesh above the parallel threshold, with 1 and 2 threads.
TEST(TetGeometry, ColourLoopGivesTheSerialLumpedMassBitForBit) {
  const auto mesh =
      shuffled(shellflow::support::box_mesh({18, 18, 18}, Vec3(1, 1, 1), [](const Vec3&) { return std::string(); }), 7);
  ASSERT_GT(mesh.num_cells(), parallel_threshold);
  const CellColouring colours =
      colour_cells(mesh.cells.connectivity, 4, mesh.num_nodes(), default_block_size(mesh.num_cells()));
  std::vector<Index> tets;
  for (const Index c : colours.order) {
    const auto cell = mesh.cells.element(c);
    tets.insert(tets.end(), cell.begin(), cell.end());
  }
  TetGeometry serial;
  compute_geometry(mesh.nodes, tets, serial);
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    TetGeometry parallel;
    compute_geometry(mesh.nodes, ElementLoop{tets, colours.block_offsets, colours.colour_offsets}, parallel);
    ASSERT_EQ(parallel.lumped_mass.size(), serial.lumped_mass.size());
    EXPECT_EQ(0, std::memcmp(parallel.lumped_mass.data(), serial.lumped_mass.data(),
                             serial.lumped_mass.size() * sizeof(double)))
        << threads << " thread(s)";
    EXPECT_EQ(parallel.volume, serial.volume);
  }
  omp_set_num_threads(omp_get_num_procs());
}
