#pragma once
// The time loop of every time-stepping run (shell dynamics, flow, mesh motion, coupled
// runs): steps until the run is done, the progress line, fields every output.every steps
// and at the last one, checkpoints (output.checkpoint_every, and when the run is stopped:
// --stop-after, --stop-at-wall, SIGINT/SIGTERM), and on a solver failure the last valid
// state written before the error is reported with where it is.
#include <chrono>
#include <filesystem>
#include <functional>
#include <optional>

#include <fmt/format.h>

#include "run_control.h"
#include "shellflow/core/error.h"
#include "shellflow/core/progress.h"

namespace shellflow::app {

/// What record() writes of the current state.
enum class Record {
  probes,             ///< the probe rows (every step)
  probes_and_fields,  ///< the probe rows and the fields' frames (every output.every steps, the last)
  fields,             ///< the fields' frames only (a stopped run's or a failed run's last state)
};

struct TimeLoop {
  long steps = 0;       ///< number of steps; 0: until more() says no
  int every = 1;        ///< fields every `every` steps (and at the last)
  double end_time = 0;  ///< for the progress line (its unit is that of advance's result)
  std::filesystem::path outdir;
  /// With steps = 0: whether another step follows `completed` steps (e.g. t < t_end).
  std::function<bool(long completed)> more;
};

/// `advance(step)` makes step `step` and returns the time reached (the progress line's
/// coordinate); `record(step, what)` records probes and/or fields of the current state;
/// `time()` is the solvers' current time (of the last valid state after a failure).
/// `control` (may be null: no checkpoints) holds the checkpoint policy and the state to
/// save; a restarted run starts after control->first_step(). Returns the number of the last
/// step made; when the run was stopped, control->stopped() says so.
inline long run_time_loop(const TimeLoop& loop, const std::function<double(long)>& advance,
                          const std::function<void(long, Record)>& record, const std::function<double()>& time,
                          RunControl* control = nullptr) {
  const auto more = [&](long completed) { return loop.steps > 0 ? completed < loop.steps : loop.more(completed); };
  const long first = control ? control->first_step() : 1;
  if (control) control->arm_signals();
  Progress progress(0.0, loop.end_time);
  long step = first;
  const auto due = [&](long s) { return s % loop.every == 0 || !more(s); };
  try {
    for (; more(step - 1); ++step) {
      const double t = advance(step);
      const bool last = !more(step);
      record(step, due(step) ? Record::probes_and_fields : Record::probes);
      progress.update(t, step);
      if (!control) continue;
      const bool stop = !last && control->stop_due(step - first + 1);
      if (control->checkpoint_due(step) || stop) control->write_checkpoint(step, time());
      if (stop) {
        if (!due(step)) record(step, Record::fields);  // after the checkpoint: a restart drops this frame
        control->mark_stopped(step, time());
        break;
      }
    }
  } catch (const SolverError& e) {
    progress.finish();
    // The solvers keep their last valid states (those of step - 1): write them before reporting.
    if (!due(step - 1)) record(step - 1, Record::fields);
    throw SolverError(fmt::format("{} (step {}); the last valid state (t = {:.6g} s) is in {}", e.what(), step,
                                  time(), loop.outdir.string()));
  }
  progress.finish();
  return control && control->stopped() ? step : step - 1;
}

}  // namespace shellflow::app
