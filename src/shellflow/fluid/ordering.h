#pragma once
// Orderings for memory locality and race-free parallel assembly: reverse Cuthill–McKee
// node renumbering and a greedy colouring of the tetrahedra (no two tetrahedra of one
// colour share a node, so each colour can scatter to nodes in parallel without atomics).
#include <span>
#include <vector>

#include "shellflow/core/types.h"
#include "shellflow/mesh/mesh.h"

namespace shellflow::fluid {

/// Reverse Cuthill–McKee order of the nodes of the cells `connectivity` (any cell type):
/// returns new_index[old_index]. Each connected component starts at a pseudo-peripheral
/// node; nodes in no cell go last.
std::vector<Index> reverse_cuthill_mckee(std::span<const Index> connectivity, int nodes_per_cell, Index num_nodes);

/// Largest |i - j| over node pairs sharing a cell (the bandwidth RCM reduces).
Index node_bandwidth(std::span<const Index> connectivity, int nodes_per_cell);

/// Renumbers the nodes of `mesh` by RCM and sorts its cells by their smallest node, so
/// that the element loop walks memory nearly sequentially. Group node lists, boundary
/// elements and cell indices follow. Returns new_index[old_index] of the nodes.
std::vector<Index> renumber_for_locality(mesh::Mesh& mesh);

/// Cells in blocks of consecutive cells, blocks grouped by colour: no two blocks of one
/// colour share a node, so the blocks of a colour can be processed by different threads
/// without atomics, while each block walks memory sequentially. Cells of block b are
/// order[block_offsets[b] .. block_offsets[b+1]); blocks of colour c are
/// [colour_offsets[c], colour_offsets[c+1]). Few colours mean few thread barriers.
struct CellColouring {
  std::vector<Index> order;
  std::vector<Index> block_offsets;
  std::vector<Index> colour_offsets;
  int num_colours() const { return static_cast<int>(colour_offsets.size()) - 1; }
  Index num_blocks() const { return static_cast<Index>(block_offsets.size()) - 1; }
};

/// Splits the cells (in their order) into blocks of `block_size` and colours the blocks
/// greedily. block_size = 1 is the plain element colouring.
CellColouring colour_cells(std::span<const Index> connectivity, int nodes_per_cell, Index num_nodes,
                           Index block_size = 1);

/// The colouring of a rank's cells that keeps the order of a whole mesh's colouring `whole`:
/// `cells` holds the rank's cells as indices into the whole mesh, increasing (local cell i is
/// whole cell cells[i]). Local blocks are the whole blocks restricted to the rank's cells (empty
/// ones dropped), in the same colours and order, so the element contributions at any node all of
/// whose cells the rank holds are added in the same order as in the whole mesh: a distributed
/// flow gives the same bits on any number of ranks (docs/parallel.md). Throws InputError for a
/// cell index outside `whole` or not increasing.
CellColouring restrict_colouring(const CellColouring& whole, std::span<const Index> cells);

/// Block size for `num_cells` cells: about 64 blocks, 256 to 8192 cells each. It does not
/// depend on the thread count, so neither does the order of the element sums (the same bits on
/// any number of threads): threads take blocks as they come (core/parallel.h).
Index default_block_size(Index num_cells);

}  // namespace shellflow::fluid
