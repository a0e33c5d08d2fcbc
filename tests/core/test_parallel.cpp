// The thread pool of the time loop (core/parallel.h): every chunk runs exactly once on any
// thread count, exact reductions, nested and concurrent calls, exceptions, and loops that
// follow each other faster than a thread wakes up.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include "shellflow/core/parallel.h"

namespace shellflow::parallel {
namespace {

/// Sets the thread count for one test and puts the old one back.
class Threads {
 public:
  explicit Threads(int n) : before_(num_threads()) { set_num_threads(n); }
  ~Threads() { set_num_threads(before_); }
  Threads(const Threads&) = delete;
  Threads& operator=(const Threads&) = delete;

 private:
  int before_;
};

TEST(ParallelFor, EveryIndexOnceOnAnyThreadCountAndGrain) {
  for (const int threads : {1, 2, 3, 5}) {
    const Threads scope(threads);
    EXPECT_EQ(num_threads(), threads);
    for (const Index n : {0, 1, 7, 1000, 100003})
      for (const Index grain : {1, 3, 64, 4096, 1000000}) {
        std::vector<std::atomic<int>> hits(std::size_t(n) + 1);
        for_range(n, grain, [&](Index begin, Index end) {
          EXPECT_LE(0, begin);
          EXPECT_LT(begin, end);
          EXPECT_LE(end, n);
          EXPECT_LE(end - begin, grain);
          EXPECT_EQ(begin % grain, 0) << "chunks start at multiples of the grain";
          for (Index i = begin; i < end; ++i) hits[std::size_t(i)].fetch_add(1);
        });
        for (Index i = 0; i < n; ++i)
          ASSERT_EQ(hits[std::size_t(i)].load(), 1)
              << "index " << i << " of " << n << ", grain " << grain << ", " << threads << " threads";
        EXPECT_EQ(hits[std::size_t(n)].load(), 0);
      }
  }
}

TEST(ParallelFor, ManyShortLoopsInARowLoseNoChunk) {
  // Loops that follow each other within microseconds: a worker still in an old loop must never
  // run a chunk of a newer one with the old body (the generation in the claim word).
  const Threads scope(3);
  std::vector<long> sums(2000, 0);
  for (std::size_t loop = 0; loop < sums.size(); ++loop) {
    std::atomic<long> sum = 0;
    for_each_chunk(Index(1 + loop % 7), [&](Index k) { sum.fetch_add(long(loop) * 100 + k); });
    sums[loop] = sum.load();
  }
  for (std::size_t loop = 0; loop < sums.size(); ++loop) {
    const long chunks = long(1 + loop % 7);
    ASSERT_EQ(sums[loop], long(loop) * 100 * chunks + chunks * (chunks - 1) / 2) << "loop " << loop;
  }
}

TEST(ParallelReduce, MinMaxOrAndIntegerSumsAreExactOnAnyThreadCount) {
  std::vector<double> x(50001);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(double(i) * 0.37) * double(i % 101);
  double expected_min = std::numeric_limits<double>::infinity();
  long expected_sum = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    expected_min = std::min(expected_min, x[i]);
    expected_sum += long(i % 13);
  }
  for (const int threads : {1, 2, 4}) {
    const Threads scope(threads);
    const double m = reduce(
        Index(x.size()), 512, std::numeric_limits<double>::infinity(),
        [&](Index b, Index e) {
          double r = std::numeric_limits<double>::infinity();
          for (Index i = b; i < e; ++i) r = std::min(r, x[std::size_t(i)]);
          return r;
        },
        [](double p, double q) { return std::min(p, q); });
    EXPECT_EQ(m, expected_min) << threads;
    const long s = reduce(
        Index(x.size()), 700, 0L,
        [&](Index b, Index e) {
          long r = 0;
          for (Index i = b; i < e; ++i) r += long(i % 13);
          return r;
        },
        [](long p, long q) { return p + q; });
    EXPECT_EQ(s, expected_sum) << threads;
    const bool any = reduce(
        Index(x.size()), 100, false, [&](Index b, Index e) { return b <= 31337 && 31337 < e; },
        [](bool p, bool q) { return p || q; });
    EXPECT_TRUE(any) << threads;
  }
}

TEST(ParallelFor, NestedLoopsRunSeriallyInsideTheBody) {
  const Threads scope(2);
  std::vector<std::atomic<int>> hits(64 * 64);
  for_each_chunk(64, [&](Index outer) {
    for_each_chunk(64, [&](Index inner) { hits[std::size_t(outer * 64 + inner)].fetch_add(1); });
  });
  for (const auto& h : hits) ASSERT_EQ(h.load(), 1);
}

TEST(ParallelFor, TwoCallersAtOnceBothFinish) {
  // A second thread calling while the pool is busy runs its loop serially.
  const Threads scope(2);
  std::atomic<long> a = 0, b = 0;
  std::thread other([&] {
    for (int r = 0; r < 200; ++r) for_range(10000, 100, [&](Index s, Index e) { b.fetch_add(e - s); });
  });
  for (int r = 0; r < 200; ++r) for_range(10000, 100, [&](Index s, Index e) { a.fetch_add(e - s); });
  other.join();
  EXPECT_EQ(a.load(), 200L * 10000);
  EXPECT_EQ(b.load(), 200L * 10000);
}

TEST(ParallelFor, AnExceptionInAChunkReachesTheCallerAfterTheLoop) {
  for (const int threads : {1, 2}) {
    const Threads scope(threads);
    std::atomic<int> done = 0;
    EXPECT_THROW(for_each_chunk(50,
                                [&](Index k) {
                                  if (k == 17) throw std::runtime_error("chunk 17");
                                  done.fetch_add(1);
                                }),
                 std::runtime_error);
    EXPECT_EQ(done.load(), 49) << "the other chunks still run";
    // The pool is usable afterwards.
    std::atomic<int> after = 0;
    for_each_chunk(50, [&](Index) { after.fetch_add(1); });
    EXPECT_EQ(after.load(), 50);
  }
}

TEST(ParallelFor, ThreadSlotsAreDistinctWithinALoop) {
  // Within one loop a slot belongs to one thread: per-thread scratch indexed by the slot is
  // never shared. Each slot's threads are recorded; every slot used must have seen exactly one
  // thread, and as many slots as threads are used.
  const Threads scope(3);
  std::mutex mutex;
  std::vector<std::set<std::thread::id>> threads_of_slot(kMaxThreads);
  std::set<std::thread::id> threads;
  std::atomic<int> total = 0;
  for_each_chunk(3000, [&](Index) {
    const int slot = detail::thread_slot();
    ASSERT_GE(slot, 0);
    ASSERT_LT(slot, 3);
    const std::lock_guard lock(mutex);
    threads_of_slot[std::size_t(slot)].insert(std::this_thread::get_id());
    threads.insert(std::this_thread::get_id());
    total.fetch_add(1);
  });
  EXPECT_EQ(total.load(), 3000);
  std::size_t slots_used = 0;
  for (const auto& owners : threads_of_slot) {
    EXPECT_LE(owners.size(), 1u) << "a slot was shared by two threads";
    slots_used += owners.empty() ? 0 : 1;
  }
  EXPECT_EQ(slots_used, threads.size());
  // Which thread takes how many chunks is up to the scheduler (under a sanitizer the workers
  // may take them all before the caller claims one): not asserted.
}

}  // namespace
}  // namespace shellflow::parallel
