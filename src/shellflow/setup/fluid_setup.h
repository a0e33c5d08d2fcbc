#pragma once
// Case file -> flow model pieces: the builders every kind of run shares (flow alone, coupled).
#include <vector>

#include "shellflow/fluid/fluid_model.h"
#include "shellflow/io/case.h"

namespace shellflow::setup {

/// Gas and scheme options of a flow section (q_dif and mass from its analysis, if any).
fluid::FluidOptions fluid_options(const io::FluidSection& section);
/// The free stream as a primitive state.
fluid::Primitive free_stream(const io::FluidSection& section);
fluid::Primitive primitive(const io::GasState& g);
fluid::Primitive primitive(const io::SpaceTimeState& s, const Vec3& X, double t);

/// The boundary conditions of a flow section. `mesh_velocity`: on a mesh moved by a
/// prescribed motion, the nodal mesh velocity of the current step, which slip and no-slip
/// walls then follow (the vector must outlive the model); null on a fixed mesh or when the
/// walls' velocities are set per node (FluidModel::set_wall_velocity, the coupled run).
std::vector<fluid::BoundaryCondition> boundary_conditions(const io::FluidSection& section,
                                                          const std::vector<Vec3>* mesh_velocity);

}  // namespace shellflow::setup
