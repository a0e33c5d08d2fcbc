#pragma once
// The parallel element loop: tetrahedra stored block by block, blocks grouped by colour
// (see CellColouring). Threads share the blocks of one colour; a barrier separates colours.
#include <span>

#include "shellflow/core/types.h"

namespace shellflow::fluid {

/// Loops over fewer items than this run on one thread: thread start-up and barriers cost
/// more than they save on small meshes (and much more on a loaded machine).
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
  const auto num_elements = static_cast<Index>(loop.tets.size() / 4);
#pragma omp parallel if (num_elements > parallel_threshold)
  for (int c = 0; c < num_colours; ++c) {
    const Index first = loop.colour_offsets[std::size_t(c)];
    const Index last = loop.colour_offsets[std::size_t(c) + 1];
#pragma omp for schedule(dynamic, 1)
    for (Index b = first; b < last; ++b)
      body(loop.block_offsets[std::size_t(b)], loop.block_offsets[std::size_t(b) + 1]);
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

}  // namespace shellflow::fluid
