#include "shellflow/core/parallel.h"

#include <linux/futex.h>
#include <omp.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace shellflow::parallel {
namespace {

// One word holds the loop being run: its generation (24 bits), its chunk count (20 bits) and
// the next unclaimed chunk (20 bits). A thread claims a chunk by one compare-and-swap on it,
// so a thread that lost its core in the middle of an old loop can never claim a chunk of a
// newer one with the old loop's body: the generation in the word differs and the swap fails.
constexpr int kChunkBits = 20;
constexpr std::uint64_t kChunkMask = (std::uint64_t{1} << kChunkBits) - 1;
constexpr Index kMaxChunks = Index(kChunkMask);

constexpr std::uint64_t pack(std::uint64_t generation, std::uint64_t total, std::uint64_t next) {
  return (generation << (2 * kChunkBits)) | (total << kChunkBits) | next;
}
constexpr std::uint64_t total_of(std::uint64_t w) { return (w >> kChunkBits) & kChunkMask; }
constexpr std::uint64_t next_of(std::uint64_t w) { return w & kChunkMask; }

// How long a thread spins before it sleeps: about the gap between two loops of a flow step,
// so that on a quiet machine the next loop finds the workers awake (SHELLFLOW_SPIN_US).
std::chrono::nanoseconds spin_time() {
  static const auto ns = [] {
    long us = 20;
    if (const char* env = std::getenv("SHELLFLOW_SPIN_US")) {
      char* end = nullptr;
      const long v = std::strtol(env, &end, 10);
      if (end != env && *end == '\0' && v >= 0 && v <= 100000) us = v;
    }
    return std::chrono::nanoseconds(us * 1000);
  }();
  return ns;
}

inline void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#else
  std::this_thread::yield();
#endif
}

/// Spins until ready() or the spin time is over; returns ready().
template <class Ready>
bool spin_until(Ready&& ready) {
  const auto start = std::chrono::steady_clock::now();
  const auto limit = spin_time();
  for (int k = 1;; ++k) {
    if (ready()) return true;
    cpu_relax();
    if (k % 64 == 0 && std::chrono::steady_clock::now() - start > limit) return ready();
  }
}

// Sleep until *word != expected (or a spurious wake-up), and wake every sleeper on word: the
// Linux futex, private to the process.
void futex_wait(std::atomic<std::uint32_t>& word, std::uint32_t expected) {
  static_assert(sizeof(std::atomic<std::uint32_t>) == sizeof(std::uint32_t));
  syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(&word), FUTEX_WAIT_PRIVATE, expected, nullptr, nullptr, 0);
}
void futex_wake_all(std::atomic<std::uint32_t>& word) {
  syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(&word), FUTEX_WAKE_PRIVATE, INT32_MAX, nullptr, nullptr, 0);
}

thread_local int tls_slot = 0;
thread_local bool tls_inside = false;  // in a loop body (or a worker): nested loops run serially

struct Inside {
  Inside() { tls_inside = true; }
  ~Inside() { tls_inside = false; }
  Inside(const Inside&) = delete;
  Inside& operator=(const Inside&) = delete;
};

class Pool {
 public:
  explicit Pool(int threads) {
    for (int t = 1; t < threads; ++t) workers_.emplace_back([this, t] { work(t); });
  }
  ~Pool() {
    stop_.store(true);
    generation_.fetch_add(1);
    futex_wake_all(generation_);
    for (auto& w : workers_) w.join();
  }
  int size() const { return int(workers_.size()) + 1; }

  void run(Index chunks, detail::ChunkFn fn, const void* context) {
    fn_ = fn;
    context_ = context;
    done_.store(0, std::memory_order_relaxed);
    total_ = std::uint32_t(chunks);
    const std::uint64_t g = (claim_.load(std::memory_order_relaxed) >> (2 * kChunkBits)) + 1;
    claim_.store(pack(g & 0xFFFFFF, std::uint64_t(chunks), 0), std::memory_order_release);
    generation_.fetch_add(1, std::memory_order_seq_cst);
    if (sleepers_.load(std::memory_order_seq_cst) > 0) futex_wake_all(generation_);
    {
      const Inside inside;
      claim_chunks();
    }
    // Wait for the chunks other threads hold: spin a little, then sleep until the last one
    // is done (a holder that lost its core gets this one's).
    if (!spin_until([&] { return done_.load(std::memory_order_acquire) == total_; })) {
      for (;;) {
        const std::uint32_t d = done_.load(std::memory_order_acquire);
        if (d == total_) break;
        caller_sleeps_.store(true, std::memory_order_seq_cst);
        if (done_.load(std::memory_order_seq_cst) != total_) futex_wait(done_, d);
        caller_sleeps_.store(false, std::memory_order_relaxed);
      }
    }
    if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
  }

 private:
  void claim_chunks() {
    std::uint64_t w = claim_.load(std::memory_order_acquire);
    while (next_of(w) < total_of(w)) {
      if (!claim_.compare_exchange_weak(w, w + 1, std::memory_order_acq_rel, std::memory_order_acquire)) continue;
      // The chunk is ours: its loop cannot end before it is done, so fn_ and context_ are
      // still that loop's.
      try {
        fn_(context_, Index(next_of(w)));
      } catch (...) {
        const std::lock_guard lock(error_mutex_);
        if (!error_) error_ = std::current_exception();
      }
      const std::uint32_t d = done_.fetch_add(1, std::memory_order_seq_cst) + 1;
      if (d == total_of(w) && caller_sleeps_.load(std::memory_order_seq_cst)) futex_wake_all(done_);
      w = claim_.load(std::memory_order_acquire);
    }
  }

  void work(int slot) {
    tls_slot = slot;
    tls_inside = true;
    // From the pool's first generation: a worker that starts late still sees every loop and
    // the stop.
    std::uint32_t seen = 0;
    for (;;) {
      if (!spin_until([&] { return generation_.load(std::memory_order_acquire) != seen; })) {
        sleepers_.fetch_add(1, std::memory_order_seq_cst);
        while (generation_.load(std::memory_order_seq_cst) == seen && !stop_.load(std::memory_order_seq_cst))
          futex_wait(generation_, seen);
        sleepers_.fetch_sub(1, std::memory_order_relaxed);
      }
      seen = generation_.load(std::memory_order_acquire);
      if (stop_.load()) return;
      claim_chunks();
    }
  }

  std::vector<std::thread> workers_;
  alignas(64) std::atomic<std::uint64_t> claim_{0};
  alignas(64) std::atomic<std::uint32_t> done_{0};
  alignas(64) std::atomic<std::uint32_t> generation_{0};
  std::atomic<int> sleepers_{0};
  std::atomic<bool> caller_sleeps_{false};
  std::atomic<bool> stop_{false};
  std::uint32_t total_ = 0;
  std::mutex error_mutex_;
  std::exception_ptr error_;  // the first exception of a loop's chunks, rethrown by its caller
  detail::ChunkFn fn_ = nullptr;
  const void* context_ = nullptr;
};

struct PoolHolder {
  std::mutex mutex;  // one loop at a time; a second caller runs its loop serially
  std::unique_ptr<Pool> pool;
};

PoolHolder& holder() {
  static PoolHolder h;
  return h;
}

}  // namespace

int num_threads() { return std::clamp(omp_get_max_threads(), 1, kMaxThreads); }

void set_num_threads(int threads) { omp_set_num_threads(std::clamp(threads, 1, kMaxThreads)); }

namespace detail {

int thread_slot() { return tls_slot; }

void run(Index chunks, ChunkFn fn, const void* context) {
  // Every chunk runs, as on the pool; the first exception is rethrown at the end.
  auto serial = [&] {
    std::exception_ptr error;
    for (Index k = 0; k < chunks; ++k) try {
        fn(context, k);
      } catch (...) {
        if (!error) error = std::current_exception();
      }
    if (error) std::rethrow_exception(error);
  };
  if (tls_inside) return serial();
  auto& h = holder();
  std::unique_lock lock(h.mutex, std::try_to_lock);
  if (!lock.owns_lock()) return serial();
  const int threads = num_threads();
  if (threads == 1) {
    lock.unlock();
    const Inside inside;
    return serial();
  }
  if (!h.pool || h.pool->size() != threads) {
    h.pool.reset();
    h.pool = std::make_unique<Pool>(threads);
  }
  for (Index first = 0; first < chunks; first += kMaxChunks) {
    const Index count = std::min(kMaxChunks, chunks - first);
    if (first == 0) {
      h.pool->run(count, fn, context);
    } else {
      struct Offset {
        ChunkFn fn;
        const void* context;
        Index first;
      } offset{fn, context, first};
      h.pool->run(
          count,
          [](const void* c, Index k) {
            const auto& o = *static_cast<const Offset*>(c);
            o.fn(o.context, o.first + k);
          },
          &offset);
    }
  }
}

}  // namespace detail
}  // namespace shellflow::parallel
