#pragma once
// Case file -> the coupled fluid–shell system (docs/coupling.md): the shell model and its
// Newmark solver, the aerodynamic model (the flow on its fluid mesh moved through the space
// mesh, piston theory, or only the fluid mesh for the mesh-motion tests), the interface
// maps, and the partitioned driver over them. Built in the order the maps need: the fluid
// wall nodes are snapped onto the shell before the flow and the mover are built.
#include <functional>
#include <memory>
#include <vector>

#include "shellflow/coupling/flow.h"
#include "shellflow/coupling/linear_flutter.h"
#include "shellflow/coupling/partitioned_solver.h"
#include "shellflow/coupling/piston_theory.h"
#include "shellflow/io/case.h"
#include "shellflow/io/case_meshes.h"
#include "shellflow/setup/fluid_setup.h"
#include "shellflow/shell/newmark_solver.h"

namespace shellflow::setup {

struct CoupledSystem {
  std::unique_ptr<shell::ShellModel> shell;
  std::unique_ptr<shell::NewmarkSolver> solver;
  std::unique_ptr<mesh::Mesh> fluid_mesh;  ///< renumbered, wall snapped (null: piston theory)
  std::vector<Index> new_index;            ///< case fluid node -> solver node
  std::unique_ptr<coupling::ShellStepMotion> motion;
  std::unique_ptr<coupling::AerodynamicModel> aerodynamics;
  coupling::FlowModel* flow = nullptr;      ///< the aerodynamic model when it is a FlowModel
  coupling::PistonLoads* piston = nullptr;  ///< ... when it is piston theory
  /// Monolithic scheme: the linear load's matrices, on the heap so that the solver's pointers to
  /// them survive a move of the system.
  std::unique_ptr<shell::SparseMatrix> piston_stiffness, piston_damping;
  std::unique_ptr<coupling::PartitionedSolver> driver;
  double reference_pressure = 0.0;  ///< p_ref of the exchanged pressure rise (free stream)
  std::unique_ptr<FlowPart> part;   ///< the flow's part of the fluid mesh (distributed runs)
};

/// A coupled run whose flow is distributed over ranks (docs/parallel.md): the flow runs on
/// rank `rank`'s part of the fluid mesh (rank_share), everything else is whole on every rank.
/// `distribute` hands the flow and the FlowModel their distributions (mpi/; the run layer's),
/// before the driver first asks for loads.
struct CoupledRanks {
  int rank = 0;
  int ranks = 1;
  std::function<void(const FlowPart&, fluid::FluidModel&, coupling::FlowModel&)> distribute;
};

/// Builds everything and sets the initial state (shell at rest, flow at the free stream).
/// Throws InputError (maps, gaps, orientation, groups) with the case file's context.
/// `ranks`: the flow on this rank's part (null, or one rank: the whole flow).
CoupledSystem build_coupled_system(const io::Case& c, const io::CaseMeshes& meshes,
                                   const CoupledRanks* ranks = nullptr);

/// The added-mass ratio of the explicit staggered scheme, rho_inf a_inf dt / (rho_s h)
/// (docs/coupling.md "Implicit coupling"); 0 without a flow.
double added_mass_ratio(const io::Case& c);

/// The piston-theory stream of a case's fluid.free_stream, wetting the face `wet_normal`
/// points out of.
coupling::PistonTheoryFlow piston_flow(const io::Case& c, const Vec3& wet_normal);
/// What a linear flutter sweep needs of a case: the panel length along the flow (the extent
/// of the shell's nodes), D = E h^3 / (12 (1 - nu^2)) and the free stream.
coupling::FlutterSetting flutter_setting(const io::Case& c, const shell::ShellModel& model);

}  // namespace shellflow::setup
