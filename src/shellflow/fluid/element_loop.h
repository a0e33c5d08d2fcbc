#pragma once
// The flow's parallel loops (core/parallel.h): the element loop over tetrahedra stored block
// by block, blocks grouped by colour (see CellColouring), whose threads share the blocks of one
// colour, one colour after the other; and the loops over nodes and over elements whose items are
// independent. The chunks do not depend on the thread count: the same bits on any number of
// threads.
#include <span>

#include "shellflow/core/parallel.h"
#include "shellflow/core/types.h"

namespace shellflow::fluid {

/// Loops over fewer items than this run on one thread: handing out chunks and waking threads
/// cost more than they save on small meshes.
inline constexpr Index parallel_threshold = 20000;
/// The same for loops over nodes: a tetrahedral mesh has 3–6 times as many elements as
/// nodes, so a mesh whose element loops run in parallel runs its node loops so too.
inline constexpr Index node_parallel_threshold = parallel_threshold / 4;

struct ElementLoop {
  std::span<const Index> tets;            ///< 4 nodes per element, in block order
  std::span<const Index> block_offsets;   ///< elements of block b: [block_offsets[b], [b+1])
  std::span<const Index> colour_offsets;  ///< blocks of colour c: [colour_offsets[c], [c+1])
};

/// Calls body(first, last) for every block of elements [first, last); blocks of one colour
/// run concurrently, so body may scatter to the nodes of its elements without atomics.
template <class Body>
void for_each_block(const ElementLoop& loop, Body&& body) {
  const int num_colours = static_cast<int>(loop.colour_offsets.size()) - 1;
  const bool threaded = static_cast<Index>(loop.tets.size() / 4) > parallel_threshold;
  for (int c = 0; c < num_colours; ++c) {
    const Index first = loop.colour_offsets[std::size_t(c)];
    const Index last = loop.colour_offsets[std::size_t(c) + 1];
    const auto block = [&](Index b) {
      body(loop.block_offsets[std::size_t(b)], loop.block_offsets[std::size_t(b) + 1]);
    };
    if (threaded) {
      parallel::for_each_chunk(last - first, [&](Index k) { block(first + k); });
    } else {
      for (Index b = first; b < last; ++b) block(b);
    }
  }
}

/// Calls body(e) for every element; elements of one colour run concurrently, so body may
/// scatter to the element's nodes without atomics.
template <class Body>
void for_each_element(const ElementLoop& loop, Body&& body) {
  for_each_block(loop, [&](Index first, Index last) {
    for (Index e = first; e < last; ++e) body(e);
  });
}

/// Calls body(a) for every node a in [0, n) (independent items), in chunks of
/// parallel::kNodeGrain; serial below node_parallel_threshold.
template <class Body>
void for_each_node(Index n, Body&& body) {
  parallel::for_range(n, parallel::grain_if(n > node_parallel_threshold, parallel::kNodeGrain, n),
                      [&](Index begin, Index end) {
                        for (Index a = begin; a < end; ++a) body(a);
                      });
}

/// Calls body(e) for every element e in [0, n) that writes only element e's entries, in
/// chunks of parallel::kElementGrain; serial below parallel_threshold.
template <class Body>
void for_each_element_index(Index n, Body&& body) {
  parallel::for_range(n, parallel::grain_if(n > parallel_threshold, parallel::kElementGrain, n),
                      [&](Index begin, Index end) {
                        for (Index e = begin; e < end; ++e) body(e);
                      });
}

/// op over value(a) of the items a in [0, n), chunks of `grain` (serial below `threshold`
/// items); op exact, commutative and associative (parallel::reduce).
template <class T, class Value, class Op>
T reduce_items(Index n, Index grain, Index threshold, T identity, Value&& value, Op&& op) {
  return parallel::reduce(
      n, parallel::grain_if(n > threshold, grain, n), identity,
      [&](Index begin, Index end) {
        T r = identity;
        for (Index a = begin; a < end; ++a) r = op(r, value(a));
        return r;
      },
      op);
}

}  // namespace shellflow::fluid
