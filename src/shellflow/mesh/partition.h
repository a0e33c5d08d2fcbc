#pragma once
// Partitions of a mesh for owner-computes parallel runs (docs/parallel.md): the cells split
// into parts by METIS (serial METIS 5.1, METIS_PartMeshDual), one owner part (rank) per node,
// and one rank's local view: its owned nodes first, then its ghost nodes; its cells are every
// cell that touches an owned node (the owned cells plus one ghost layer), so that every owned
// node's residual is complete without communication; and the exchange lists of ghost values
// with each neighbour rank.
//
// Everything here is deterministic: the same mesh and part count give the same parts, owners,
// local numbering and lists on every machine and every call.
#include <span>
#include <vector>

#include "shellflow/core/types.h"
#include "shellflow/mesh/mesh.h"

namespace shellflow::mesh {

/// The part (0 .. parts-1) of every cell: METIS_PartMeshDual, k-way, on the cells' vertices
/// (the first num_vertices nodes of each cell), two cells adjacent when they share a face
/// (3 vertices for tetrahedra, 2 for triangles), with fixed options (seed 1, contiguous parts
/// where METIS can make them). `parts == 1` gives all zeros without calling METIS.
/// Throws InputError when `parts` is below 1 or above the number of cells, Error naming the
/// METIS return code when METIS fails.
std::vector<int> partition_cells(const Mesh& mesh, int parts);

/// The owner part of every node: the part of the lowest-indexed cell containing the node
/// (any node of the cell, not only its vertices); 0 for a node in no cell. `cell_part` holds
/// one part per cell (partition_cells). Throws InputError when its size is not the number of
/// cells or a part is negative.
std::vector<int> node_owners(const Mesh& mesh, std::span<const int> cell_part);

/// The exchange lists of one rank with one neighbour rank, in the rank's local node indices.
/// Rank r's `receive` from s and s's `send` to r name the same global nodes in the same
/// order (increasing global index).
struct NeighbourLists {
  int rank = 0;                ///< the neighbour
  std::vector<Index> send;     ///< owned nodes the neighbour holds as ghosts
  std::vector<Index> receive;  ///< ghost nodes the neighbour owns
};

/// One rank's part of a mesh. Local node i is global node nodes[i]; the first `num_owned`
/// are the rank's owned nodes (increasing global index), the rest its ghost nodes (increasing
/// global index).
struct LocalPart {
  int rank = 0;
  std::vector<Index> nodes;                ///< local -> global node index: owned, then ghosts
  Index num_owned = 0;                     ///< owned nodes: nodes[0 .. num_owned)
  std::vector<Index> cells;                ///< global indices (increasing) of every cell with an owned node
  std::vector<Index> connectivity;         ///< the nodes of `cells` in local indices (Gmsh order)
  std::vector<NeighbourLists> neighbours;  ///< one per neighbour rank, by increasing rank

  Index num_nodes() const { return static_cast<Index>(nodes.size()); }
  Index num_ghosts() const { return num_nodes() - num_owned; }
};

/// The local part of `rank` for the node owners `node_owner` (node_owners). A rank that owns
/// no node gets an empty part. Throws InputError when `node_owner` does not hold one entry
/// per node or `rank` is negative.
LocalPart make_local_part(const Mesh& mesh, std::span<const int> node_owner, int rank);

/// The mesh of one rank: the local nodes (coordinates and node tags, in local order) and
/// cells (in the order of part.cells), named like `mesh`, and each physical group restricted
/// to the part: a lower-dimensional group keeps the elements all of whose nodes are local and
/// whose vertices all lie in one local cell; a group of the mesh's dimension keeps its local
/// cells (re-indexed to local cells, increasing) and their elements; a group's node list holds
/// the nodes of its kept elements (for a group without elements: its local nodes), in local
/// indices, sorted. Every group of `mesh` is present (maybe empty), so that group names
/// resolve on every rank. Every element of a group that touches an owned node is kept.
Mesh local_mesh(const Mesh& mesh, const LocalPart& part);

/// Sizes of one part (rank).
struct PartStats {
  Index owned_nodes = 0;
  Index ghost_nodes = 0;
  Index owned_cells = 0;      ///< cells METIS put in the part
  Index ghost_cells = 0;      ///< cells of the local part (LocalPart::cells) of another part
  Index local_cells = 0;      ///< LocalPart::cells: the cells the rank computes
  int neighbours = 0;         ///< ranks it exchanges values with
  Index interface_nodes = 0;  ///< owned nodes sent to some neighbour
  double halo_share = 0.0;    ///< ghost_nodes / owned_nodes (ghost_nodes when it owns none)
};

/// The sizes of every part, their totals and the balance figures of a partition.
struct PartitionStats {
  std::vector<PartStats> parts;
  Index nodes = 0;               ///< sum of the owned nodes (the mesh's nodes)
  Index cells = 0;               ///< sum of the owned cells (the mesh's cells)
  Index ghost_nodes = 0;         ///< sum over parts
  Index ghost_cells = 0;         ///< sum over parts
  Index interface_nodes = 0;     ///< sum over parts
  double imbalance = 1.0;        ///< max owned cells / mean owned cells
  double work_imbalance = 1.0;   ///< max local cells / mean local cells (owned + ghost layer)
  double max_halo_share = 0.0;   ///< max over parts of ghost / owned nodes
  double mean_halo_share = 0.0;  ///< mean over parts of ghost / owned nodes
};

/// The statistics of a partition (cell parts and node owners as given by partition_cells and
/// node_owners; the number of parts is one more than the largest part of either). The same
/// counts as make_local_part gives rank by rank, in one pass over the cells. Throws
/// InputError when the sizes do not match the mesh or a part is negative.
PartitionStats partition_stats(const Mesh& mesh, std::span<const int> cell_part, std::span<const int> node_owner);

}  // namespace shellflow::mesh
