#pragma once
// The time loop of the runs (shell dynamics, flow, coupled runs): steps until the run is
// done, the progress line, fields every output.every steps and at the last one, and on a
// solver failure the last valid state written before the error is reported with where it is.
#include <filesystem>
#include <functional>

#include <fmt/format.h>

#include "shellflow/core/error.h"
#include "shellflow/core/progress.h"

namespace shellflow::app {

struct TimeLoop {
  long steps = 0;       ///< number of steps; 0: until more() says no
  int every = 1;        ///< fields every `every` steps (and at the last)
  double end_time = 0;  ///< for the progress line (its unit is that of advance's result)
  std::filesystem::path outdir;
  /// With steps = 0: whether another step follows `completed` steps (e.g. t < t_end).
  std::function<bool(long completed)> more;
};

/// `advance(step)` makes step `step` and returns the time reached (the progress line's
/// coordinate); `record(step, fields)` records probes (and fields when asked) of the current
/// state; `time()` is the solvers' current time (of the last valid state after a failure).
/// Returns the number of steps made.
inline long run_time_loop(const TimeLoop& loop, const std::function<double(long)>& advance,
                          const std::function<void(long, bool)>& record, const std::function<double()>& time) {
  const auto more = [&](long completed) { return loop.steps > 0 ? completed < loop.steps : loop.more(completed); };
  Progress progress(0.0, loop.end_time);
  long step = 1;
  try {
    for (; more(step - 1); ++step) {
      const double t = advance(step);
      record(step, step % loop.every == 0 || !more(step));
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
  return step - 1;
}

}  // namespace shellflow::app
