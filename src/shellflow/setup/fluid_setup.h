#pragma once
// Case file -> flow model pieces: the builders every kind of run shares (flow alone, coupled).
#include <memory>
#include <vector>

#include "shellflow/fluid/fluid_model.h"
#include "shellflow/io/case.h"
#include "shellflow/mesh/mesh.h"

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

/// The boundary conditions of a flow section. `mesh_velocity`: on a mesh moved by a
/// prescribed motion, the nodal mesh velocity of the current step, which slip and no-slip
/// walls then follow (the vector must outlive the model); null on a fixed mesh or when the
/// walls' velocities are set per node (FluidModel::set_wall_velocity, the coupled run).
std::vector<fluid::BoundaryCondition> boundary_conditions(const io::FluidSection& section,
                                                          const std::vector<Vec3>* mesh_velocity);

/// The flow of a flow run: the case's fluid mesh renumbered for memory locality
/// (new_index[i] is the solver's node of case node i), its boundary conditions and its
/// initial state (the analysis's Riemann problem or initial field, else the free stream).
/// With a prescribed mesh motion (fluid.mesh_motion), `mesh_velocity` holds the nodal mesh
/// velocity the walls follow, set to the motion's at t = 0.
struct Flow {
  std::unique_ptr<fluid::FluidModel> model;
  std::vector<Index> new_index;
  std::unique_ptr<std::vector<Vec3>> mesh_velocity;  ///< null on a fixed mesh
};
Flow build_flow(const io::FluidSection& section, const mesh::Mesh& case_mesh);

}  // namespace shellflow::setup
