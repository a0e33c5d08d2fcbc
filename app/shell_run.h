#pragma once
// A shell run: static load stepping or Newmark dynamics of the case's shell, driven by the
// case file's supports, loads and analysis (no flow).
#include "run_context.h"

namespace shellflow::app {

/// Static: probes.csv rows are load levels (the `time` column holds the load factor);
/// dynamic: time steps from 0 to time.end. Writes shell_NNNNNN.vtu + shell.pvd every
/// output.every steps (and the last one). Throws SolverError when Newton fails for good.
void run_shell(const RunContext& run);

}  // namespace shellflow::app
