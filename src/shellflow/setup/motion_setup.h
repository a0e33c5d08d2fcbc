#pragma once
// Case file -> mesh-motion pieces shared by the mesh-motion runs and the coupled runs.
#include <memory>

#include "shellflow/io/case.h"
#include "shellflow/io/case_meshes.h"
#include "shellflow/motion/boundary_motion.h"
#include "shellflow/motion/mesh_mover.h"
#include "shellflow/motion/space_mesh.h"

namespace shellflow::setup {

/// The space-mesh options of a motion section (groups, IDW exponents, weighting).
motion::SpaceMeshOptions space_mesh_options(const io::MotionSection& m);

/// The prescribed boundary motion of a mesh-motion run (motion.prescribed: panel modes).
/// Throws InputError at the section when it has none.
std::unique_ptr<motion::PanelModesMotion> prescribed_motion(const io::MotionSection& m);

/// The mover of the fluid mesh by the motion section's method: the space mesh (IDW samples:
/// the shell's nodes when the case has a shell mesh, else the fluid mesh's interface nodes),
/// direct IDW or Laplace smoothing, driven by `boundary` (which must outlive it).
std::unique_ptr<motion::FluidMeshMover> build_mover(const io::MotionSection& m, const io::CaseMeshes& meshes,
                                                    motion::BoundaryMotion& boundary);

}  // namespace shellflow::setup
