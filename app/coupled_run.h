#pragma once
// A coupled fluid–shell run (a case with a `coupling` section): the shell and the flow (or
// piston theory, or only the fluid mesh) advanced together by the partitioned driver.
#include "run_context.h"

namespace shellflow::app {

/// Steps from t = 0 to time.end by time.step; writes shell_/fluid_/space_NNNNNN.vtu + .pvd
/// every output.every steps, coupling.csv (Newton iterations, sub-steps, force balance) and
/// the probes every step, mesh_quality.csv when the fluid mesh moves, and the flutter plots.
/// On a solver failure the last valid state is written before the error is reported.
void run_coupled(const RunContext& run);

}  // namespace shellflow::app
