#pragma once
// The threads of the time loop: one pool of workers that share a loop's chunks with the calling
// thread, made for a machine that other programs share (docs/parallel.md "Threads").
//
// - Chunks are claimed one at a time by whichever thread runs (no static split): a thread that
//   loses its core to another program simply takes fewer chunks, and a loop ends when its last
//   chunk is done, not when every thread has checked in.
// - A waiting thread spins for a few tens of microseconds, then sleeps in the kernel (futex):
//   the next loop of a step starts without a wake-up on a quiet machine, and a thread that
//   waits longer gives its core back to the threads doing the work.
// - The chunks are fixed by the loop (n and grain), not by the thread count, so a loop whose
//   chunks write disjoint data, or that reduces with an exact operation (min, max, or, integer
//   sums), gives the same bits on any number of threads. Floating sums: one partial per chunk,
//   added in chunk order by the caller.
// - Serial where it does not pay: one thread, one chunk, or a call from inside a loop body.
//
// The thread count is the OpenMP runtime's (omp_get_max_threads(): OMP_NUM_THREADS, else the
// number of cores, or what omp_set_num_threads set last), read at every loop: the pool follows
// it.
#include <algorithm>
#include <array>
#include <cstdint>

#include "shellflow/core/types.h"

namespace shellflow::parallel {

/// Threads a loop may use (the caller included): omp_get_max_threads() in [1, kMaxThreads].
int num_threads();
/// omp_set_num_threads(threads) (1 = serial), clamped to [1, kMaxThreads].
void set_num_threads(int threads);
inline constexpr int kMaxThreads = 64;

namespace detail {
using ChunkFn = void (*)(const void* context, Index chunk);
/// Runs fn(context, k) for k in [0, chunks) on the pool; returns when all are done.
void run(Index chunks, ChunkFn fn, const void* context);
/// The calling thread's place in the pool: 0 for the caller of a loop, 1.. for the workers.
int thread_slot();
}  // namespace detail

/// Calls body(k) for every chunk k in [0, chunks), chunks shared among the threads.
template <class Body>
void for_each_chunk(Index chunks, Body&& body) {
  if (chunks <= 0) return;
  if (chunks == 1) {
    body(Index{0});
    return;
  }
  detail::run(
      chunks, [](const void* c, Index k) { (*static_cast<const std::remove_reference_t<Body>*>(c))(k); }, &body);
}

/// The grain of a loop over n items that runs threaded only when `threaded`: `grain`, else n
/// (one chunk: the loop runs on the calling thread).
inline Index grain_if(bool threaded, Index grain, Index n) { return threaded ? grain : std::max<Index>(n, 1); }

/// Number of chunks of `grain` items that cover n items.
inline Index num_chunks(Index n, Index grain) { return n <= 0 ? 0 : (n + grain - 1) / std::max<Index>(grain, 1); }

/// Calls body(begin, end) for the chunks [k grain, min(n, (k + 1) grain)) of [0, n).
template <class Body>
void for_range(Index n, Index grain, Body&& body) {
  grain = std::max<Index>(grain, 1);
  for_each_chunk(num_chunks(n, grain), [&](Index k) { body(k * grain, std::min(n, (k + 1) * grain)); });
}

/// op over map(begin, end) of the chunks of [0, n), starting from `identity`. op must be exact,
/// commutative and associative (min, max, logical or/and, integer sums): the partials are
/// combined per thread, in no fixed order.
template <class T, class Map, class Op>
T reduce(Index n, Index grain, T identity, Map&& map, Op&& op) {
  struct alignas(64) Slot {
    T value;
  };
  std::array<Slot, kMaxThreads> partial;
  for (auto& s : partial) s.value = identity;
  for_range(n, grain, [&](Index begin, Index end) {
    T& mine = partial[std::size_t(detail::thread_slot())].value;
    mine = op(mine, map(begin, end));
  });
  T result = identity;
  for (const auto& s : partial) result = op(result, s.value);
  return result;
}

/// Grains of the flow's loops: nodes and elements per chunk (a few tens of microseconds of
/// work; a mesh of fewer items runs on one thread).
inline constexpr Index kNodeGrain = 2048;
inline constexpr Index kElementGrain = 4096;

}  // namespace shellflow::parallel
