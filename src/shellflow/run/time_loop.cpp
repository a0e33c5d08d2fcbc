#include "shellflow/run/time_loop.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "shellflow/core/error.h"
#include "shellflow/core/progress.h"

namespace shellflow::run {

long run_time_loop(const TimeLoop& loop, const std::function<double(long)>& advance,
                   const std::function<void(long, Record)>& record, const std::function<double()>& time,
                   RunControl* control) {
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
    throw SolverError(fmt::format("{} (step {}); the last valid state (t = {:.6g} s) is in {}", e.what(), step, time(),
                                  loop.outdir.string()));
  }
  progress.finish();
  return control && control->stopped() ? step : step - 1;
}

namespace {

/// A checkpoint's step is one this run makes: a restart continues a run.
void check_restart_step(const RunControl& control, const TimeLoop& loop) {
  const io::Checkpoint& c = *control.restart();
  const long step = c.header.step;
  if (loop.steps > 0 && step > loop.steps)
    throw Error(fmt::format(
        "{}: step {} (t = {:.6g} s) is after the end of this run ({} steps, time.end = {:.6g} s); raise time.end "
        "(--set time.end=...) to continue it",
        c.file.string(), step, c.header.time, loop.steps, loop.end_time));
}

/// A restart from the run's last step makes no step and writes the end-of-run files (of a run
/// killed before it wrote them); said once the state is restored (a loop that ends by its time
/// or convergence knows only then).
void log_restart_at_the_end(const RunControl& control, const TimeLoop& loop) {
  const io::Checkpoint& c = *control.restart();
  const long step = c.header.step;
  if (loop.steps > 0 ? step == loop.steps : (loop.more && !loop.more(step)))
    spdlog::info("{}: step {} is the last of this run: no step to make; writing its end-of-run files", c.file.string(),
                 step);
}

}  // namespace

long step_in_time(RunControl& control, Recorder& recorder, const TimeStepping& s) {
  recorder.register_outputs(control);
  control.set_state(s.kind, s.save, s.restore);
  if (control.restarting()) {
    check_restart_step(control, s.loop);  // before any file is touched
    control.restore(s.time, s.loop.steps, s.loop.end_time);
    log_restart_at_the_end(control, s.loop);
  } else {
    if (s.before_frame_0) s.before_frame_0();
    mpi::on_every_rank(control.ranks(), [&] { recorder.record(0, s.time(), Record::probes_and_fields); });
  }
  // On ranks a failed write (rank 0's) ends every rank at once.
  const auto record = [&](long step, Record what) {
    mpi::on_every_rank(control.ranks(), [&] { recorder.record(step, s.time(), what); });
  };
  return run_time_loop(s.loop, s.advance, record, s.time, &control);
}

}  // namespace shellflow::run
