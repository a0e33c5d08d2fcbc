#pragma once
// Case file -> mesh-motion pieces shared by the mesh-motion runs and the coupled runs.
#include "shellflow/io/case.h"
#include "shellflow/motion/space_mesh.h"

namespace shellflow::setup {

/// The space-mesh options of a motion section (groups, IDW exponents, weighting).
motion::SpaceMeshOptions space_mesh_options(const io::MotionSection& m);

}  // namespace shellflow::setup
