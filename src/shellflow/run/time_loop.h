#pragma once
// The time loop of every time-stepping run (shell dynamics, flow, mesh motion, coupled
// runs): steps until the run is done, the progress line, fields every output.every steps
// and at the last one, checkpoints (output.checkpoint_every, and when the run is stopped:
// --stop-after, --stop-at-wall, SIGINT/SIGTERM), and on a solver failure the last valid
// state written before the error is reported with where it is.
#include <filesystem>
#include <functional>
#include <string>

#include "shellflow/core/archive.h"
#include "shellflow/run/recorder.h"
#include "shellflow/run/run_control.h"

namespace shellflow::run {

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
long run_time_loop(const TimeLoop& loop, const std::function<double(long)>& advance,
                   const std::function<void(long, Record)>& record, const std::function<double()>& time,
                   RunControl* control = nullptr);

/// A time-stepping run kind, as it hands itself to the one loop.
struct TimeStepping {
  std::string kind;  ///< names the state in checkpoints ("shell dynamics", "flow", ...)
  TimeLoop loop;
  std::function<double(long)> advance;  ///< makes step n, returns the progress coordinate
  std::function<double()> time;         ///< the solvers' time (of the last valid state)
  std::function<void(ArchiveWriter&)> save;
  std::function<void(ArchiveReader&)> restore;
  /// A new run's preparation before frame 0 is recorded (may be empty).
  std::function<void()> before_frame_0;
};

/// Registers the recorder's writers and the state with `control`, puts a restarted run back
/// to its checkpoint or records frame 0 of a new one, then runs the loop. Returns the last
/// step made.
long step_in_time(RunControl& control, Recorder& recorder, const TimeStepping& stepping);

}  // namespace shellflow::run
