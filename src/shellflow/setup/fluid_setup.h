#pragma once
// Case file -> flow model pieces: the builders every kind of run shares (flow alone, coupled).
#include <functional>
#include <memory>
#include <vector>

#include "shellflow/fluid/fluid_model.h"
#include "shellflow/io/case.h"
#include "shellflow/mesh/mesh.h"
#include "shellflow/mesh/partition.h"

namespace shellflow::setup {

/// Gas and scheme options of a flow section (q_dif and mass from its analysis, if any).
fluid::FluidOptions fluid_options(const io::FluidSection& section);
/// The free stream's speed U = M a, a = sqrt(gamma p / rho): the one conversion of the case's
/// Mach number to a velocity (the flow's free stream, piston theory, the initial state).
double free_stream_speed(const io::FluidSection& section);
/// The free stream as a primitive state: velocity free_stream_speed() along its direction.
fluid::Primitive free_stream(const io::FluidSection& section);
fluid::Primitive primitive(const io::GasState& g);
fluid::Primitive primitive(const io::SpaceTimeState& s, const Vec3& X, double t);
/// The flow at t = 0 of flow-only and coupled runs alike: fluid.analysis.riemann, else fluid.analysis.initial (at
/// t = 0), else the free stream.
std::function<fluid::Primitive(const Vec3&)> initial_state(const io::FluidSection& section);

/// The boundary conditions of a flow section. `mesh_velocity`: on a mesh moved by a
/// prescribed motion, the nodal mesh velocity of the current step, which slip and no-slip
/// walls then follow (the vector must outlive the model); null on a fixed mesh or when the
/// walls' velocities are set per node (FluidModel::set_wall_velocity, the coupled run).
std::vector<fluid::BoundaryCondition> boundary_conditions(const io::FluidSection& section,
                                                          const std::vector<Vec3>* mesh_velocity);

/// One rank's share of a flow distributed over `ranks` ranks (docs/parallel.md): the whole
/// renumbered mesh (every rank holds it), the owner of each of its nodes (METIS parts of the
/// cells, mesh::node_owners), and the rank's local part, on whose local mesh the rank's model
/// runs.
struct FlowPart {
  Index whole_nodes = 0;        ///< nodes of the whole renumbered mesh
  std::vector<int> node_owner;  ///< owner rank of each node of the whole mesh
  mesh::LocalPart local;        ///< this rank's: local node i is whole node local.nodes[i]
  int ranks = 1;
};

/// Rank `rank`'s share of the renumbered mesh `whole` on `ranks` ranks: its part, and the
/// local mesh and colouring its model runs on (the whole mesh's colouring restricted to it).
struct RankShare {
  std::unique_ptr<FlowPart> part;
  mesh::Mesh mesh;
  fluid::CellColouring colouring;
};
RankShare rank_share(const mesh::Mesh& whole, int rank, int ranks);

/// The flow of a flow run: the case's fluid mesh renumbered for memory locality
/// (new_index[i] is the solver's node of case node i), its boundary conditions and its
/// initial state (the analysis's Riemann problem or initial field, else the free stream).
/// With a prescribed mesh motion (fluid.mesh_motion), `mesh_velocity` holds the nodal mesh
/// velocity the walls follow, set to the motion's at t = 0.
///
/// With `ranks` > 1 the model is rank `rank`'s part (`part`): the renumbered mesh is split by
/// METIS into `ranks` parts, and the model runs on the rank's local mesh with the whole mesh's
/// colouring restricted to it (the same bits on any rank count); new_index still maps case
/// nodes to the whole renumbered mesh, part->local maps those to the model's nodes. The caller
/// hands the model its distribution (mpi/flow_distribution.h). Every rank computes the same
/// partition (METIS with a fixed seed, rank_share).
struct Flow {
  std::unique_ptr<fluid::FluidModel> model;
  std::vector<Index> new_index;
  std::unique_ptr<std::vector<Vec3>> mesh_velocity;  ///< null on a fixed mesh
  std::unique_ptr<FlowPart> part;                    ///< null in one process
};
Flow build_flow(const io::FluidSection& section, const mesh::Mesh& case_mesh, int rank = 0, int ranks = 1);

}  // namespace shellflow::setup
