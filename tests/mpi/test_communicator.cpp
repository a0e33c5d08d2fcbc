// Ranks of a distributed run (mpi/, docs/parallel.md), run under mpirun with 1, 2 and 3 ranks
// (CTest label mpi): the partition of a box mesh computed on every rank is the same
// everywhere, every cell and node is owned once over the ranks, ghosts are complete; the halo
// exchange sets every ghost to its owner's value; reductions; an error on one rank reaches
// every rank as the same message.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "shellflow/mesh/partition.h"
#include "shellflow/mpi/communicator.h"
#include "shellflow/mpi/halo_exchange.h"
#include "support/box_mesh.h"

namespace shellflow::mpi {
namespace {

mesh::Mesh box() {
  return support::box_mesh({9, 7, 5}, Vec3(1.0, 0.8, 0.6),
                           [](const Vec3& c) { return c.x() < 1e-12 ? std::string("inflow") : std::string("walls"); });
}

/// The partition of the box into the world's ranks, as every rank computes it.
struct World {
  Communicator& comm = Communicator::world();
  mesh::Mesh global = box();
  std::vector<int> cell_part = mesh::partition_cells(global, comm.size());
  std::vector<int> owner = mesh::node_owners(global, cell_part);
  mesh::LocalPart part = mesh::make_local_part(global, owner, comm.rank());
};

double value_of(Index global_node, int field) { return 1000.0 * field + std::sqrt(double(global_node) + 0.5); }

TEST(DistributedPartition, EveryRankComputesTheSamePartsAndEachCellAndNodeIsOwnedOnce) {
  const World w;
  // The same parts on every rank: a checksum of the partition, compared by min and max.
  double checksum = 0.0;
  for (std::size_t c = 0; c < w.cell_part.size(); ++c) checksum += double(w.cell_part[c]) * double(c % 97 + 1);
  EXPECT_EQ(w.comm.min(checksum), w.comm.max(checksum));
  long owned_cells = 0;
  for (const int p : w.cell_part) owned_cells += p == w.comm.rank() ? 1 : 0;
  EXPECT_EQ(w.comm.sum(owned_cells), long(w.global.num_cells()));
  EXPECT_EQ(w.comm.sum(long(w.part.num_owned)), long(w.global.num_nodes()));
  // Each global node owned by exactly one rank: the sum over ranks of an indicator is 1 everywhere.
  std::vector<double> mine(std::size_t(w.global.num_nodes()), 0.0);
  for (Index i = 0; i < w.part.num_owned; ++i) mine[std::size_t(w.part.nodes[std::size_t(i)])] = 1.0;
  const std::vector<double> all = w.comm.all_gather(mine);
  for (std::size_t a = 0; a < mine.size(); ++a) {
    double count = 0.0;
    for (int r = 0; r < w.comm.size(); ++r) count += all[std::size_t(r) * mine.size() + a];
    ASSERT_EQ(count, 1.0) << "node " << a;
  }
  // Ghost completeness: every cell of an owned node is a local cell, every node of a local
  // cell a local node.
  std::vector<char> local_cell(std::size_t(w.global.num_cells()), 0), local_node(mine.size(), 0);
  for (const Index c : w.part.cells) local_cell[std::size_t(c)] = 1;
  for (const Index n : w.part.nodes) local_node[std::size_t(n)] = 1;
  for (Index c = 0; c < w.global.num_cells(); ++c) {
    bool touches_owned = false;
    for (const Index n : w.global.cells.element(c)) {
      touches_owned = touches_owned || w.owner[std::size_t(n)] == w.comm.rank();
      if (local_cell[std::size_t(c)]) {
        ASSERT_TRUE(local_node[std::size_t(n)]) << "cell " << c << " node " << n;
      }
    }
    ASSERT_EQ(bool(local_cell[std::size_t(c)]), touches_owned) << "cell " << c;
  }
}

TEST(HaloExchange, EveryGhostGetsItsOwnersValueForFiveFieldsInARow) {
  const World w;
  HaloExchange halo(w.comm, w.part);
  if (w.comm.size() > 1) {
    EXPECT_GT(halo.num_neighbours(), 0u);
  }
  const std::size_t n = std::size_t(w.part.num_nodes());
  for (int round = 0; round < 3; ++round) {
    std::vector<std::vector<double>> fields(5, std::vector<double>(n, std::numeric_limits<double>::quiet_NaN()));
    for (int f = 0; f < 5; ++f)
      for (Index i = 0; i < w.part.num_owned; ++i)
        fields[std::size_t(f)][std::size_t(i)] = value_of(w.part.nodes[std::size_t(i)], f + round);
    std::vector<double*> pointers;
    for (auto& f : fields) pointers.push_back(f.data());
    halo.exchange(pointers);
    for (int f = 0; f < 5; ++f)
      for (std::size_t i = 0; i < n; ++i)
        ASSERT_EQ(fields[std::size_t(f)][i], value_of(w.part.nodes[i], f + round))
            << "rank " << w.comm.rank() << ", local node " << i
            << (Index(i) < w.part.num_owned ? " (owned)" : " (ghost)") << ", field " << f << ", round " << round;
  }
}

TEST(Reductions, MinMaxSumsAndOrOverTheRanks) {
  Communicator& comm = Communicator::world();
  const int r = comm.rank(), p = comm.size();
  EXPECT_EQ(comm.min(10.0 + r), 10.0);
  EXPECT_EQ(comm.max(10.0 + r), 10.0 + p - 1);
  EXPECT_EQ(comm.sum(long(r + 1)), long(p) * (p + 1) / 2);
  EXPECT_EQ(comm.any(r == p - 1), true);
  EXPECT_EQ(comm.any(false), false);
  // Added in rank order on every rank: the same bits everywhere.
  const double s = comm.sum_in_rank_order(0.1 * (r + 1));
  double expected = 0.0;
  for (int k = 0; k < p; ++k) expected += 0.1 * (k + 1);
  EXPECT_EQ(s, expected);
  std::string text = r == 0 ? "from rank 0" : "";
  comm.broadcast(text);
  EXPECT_EQ(text, "from rank 0");
}

TEST(Errors, AnErrorOnOneRankReachesEveryRankAsTheSameLine) {
  Communicator& comm = Communicator::world();
  EXPECT_EQ(comm.first_error(""), "");
  const int bad = comm.size() - 1;  // the last rank fails (rank 0 alone on one rank)
  const std::string mine =
      comm.rank() == bad ? "fluid state not physical at node 7 on rank " + std::to_string(bad) : "";
  EXPECT_EQ(comm.first_error(mine), "fluid state not physical at node 7 on rank " + std::to_string(bad));
  // Two ranks with an error: the lowest one's message.
  const std::string two = comm.rank() >= comm.size() - 2 ? "error of rank " + std::to_string(comm.rank()) : "";
  EXPECT_EQ(comm.first_error(two), "error of rank " + std::to_string(std::max(0, comm.size() - 2)));
}

TEST(Errors, RanksLeavingTogetherAgreeAndARankLeftAloneFindsOut) {
  Communicator& comm = Communicator::world();
  // Every rank on its way out: they agree at once.
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_TRUE(comm.all_leave_within(10.0));
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
  if (comm.size() == 1) return;
  // The last rank leaves alone while the others wait in a collective of the run: it finds out
  // within its wait, and the collective it left them in is not disturbed.
  const int alone = comm.size() - 1;
  if (comm.rank() == alone) {
    EXPECT_FALSE(comm.all_leave_within(0.3));
  }
  comm.barrier();  // the run's collective (the others waited here)
  // The ranks that did not take part join its exit barrier now, so that it completes and the
  // next test starts clean.
  if (comm.rank() != alone) {
    EXPECT_TRUE(comm.all_leave_within(10.0));
  }
  comm.barrier();
}

}  // namespace
}  // namespace shellflow::mpi

// Every rank runs every test; rank 0 prints; every rank exits with the same code.
int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  auto& comm = shellflow::mpi::Communicator::world();
  if (comm.rank() != 0) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  const int failed = RUN_ALL_TESTS() != 0 ? 1 : 0;
  const long failures = comm.sum(long(failed));
  if (comm.rank() == 0 && failures > 0) std::fprintf(stderr, "%ld rank(s) failed\n", failures);
  return failures > 0 ? 1 : 0;
}
