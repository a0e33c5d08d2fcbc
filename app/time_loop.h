#pragma once
// The time loop of the fixed-step runs (shell dynamics, coupled runs): steps 1..n, the
// progress line, fields every output.every steps and at the last one, and on a solver
// failure the last valid state written before the error is reported with where it is.
#include <filesystem>
#include <functional>

#include <fmt/format.h>

#include "shellflow/core/error.h"
#include "shellflow/core/progress.h"

namespace shellflow::app {

struct TimeLoop {
  long steps = 0;       ///< number of steps
  int every = 1;        ///< fields every `every` steps (and at the last)
  double end_time = 0;  ///< for the progress line
  std::filesystem::path outdir;
};

/// `advance(step)` makes step `step` and returns the time reached; `record(step, fields)`
/// records probes (and fields when asked) of the current state; `time()` is the solvers'
/// current time (of the last valid state after a failure).
inline void run_time_loop(const TimeLoop& loop, const std::function<double(long)>& advance,
                          const std::function<void(long, bool)>& record, const std::function<double()>& time) {
  Progress progress(0.0, loop.end_time);
  long step = 1;
  try {
    for (; step <= loop.steps; ++step) {
      const double t = advance(step);
      record(step, step % loop.every == 0 || step == loop.steps);
      progress.update(t, step);
    }
  } catch (const SolverError& e) {
    progress.finish();
    // The solvers keep their last valid states: write them before reporting.
    record(step, true);
    throw SolverError(fmt::format("{} (step {}); the last valid state (t = {:.6g} s) is in {}", e.what(), step,
                                  time(), loop.outdir.string()));
  }
  progress.finish();
}

}  // namespace shellflow::app
