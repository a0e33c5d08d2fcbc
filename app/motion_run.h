#pragma once
// A mesh-motion run: the fluid mesh follows a prescribed boundary motion through the case's
// mesh mover (space mesh, direct IDW or Laplacian), with quality monitoring.
#include "run_context.h"

namespace shellflow::app {

/// Steps from t = 0 to time.end; writes fluid_/space_NNNNNN.vtu + .pvd every output.every
/// steps, motion_quality.csv every step and the probes. Stops with SolverError (after the
/// last valid state is written) when a fluid element inverts.
void run_mesh_motion(const RunContext& run);

}  // namespace shellflow::app
