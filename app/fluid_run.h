#pragma once
// A flow run on a fixed mesh: transient (global CFL step to time.end) or steady (local time
// steps), from the free stream or a Riemann problem.
#include "run_context.h"

namespace shellflow::app {

/// Writes fluid_NNNNNN.vtu + fluid.pvd (density, velocity, pressure, Mach, temperature)
/// every output.every steps and at the end, and the probes every step. A SolverError (e.g.
/// negative pressure) stops the run after the last valid state was written.
void run_fluid(const RunContext& run);

}  // namespace shellflow::app
