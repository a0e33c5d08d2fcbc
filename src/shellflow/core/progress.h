#pragma once
// A one-line progress report (time, step, ETA) for long runs, redrawn in place when
// stdout is a terminal and silent otherwise (logs and CI output stay clean).
#include <chrono>
#include <string>

namespace shellflow {

class Progress {
 public:
  /// `end_time`: simulated time at which the run ends (> start_time).
  Progress(double start_time, double end_time, bool enabled);
  /// Enabled when stdout is a terminal, and not under an MPI launcher (mpirun gives the ranks a
  /// terminal even when its own output goes to a file).
  Progress(double start_time, double end_time);
  ~Progress();

  /// Reports that `step` has reached simulated `time`; redraws at most every 0.2 s.
  void update(double time, long step);
  /// Ends the line.
  void finish();

  /// The line for this state, e.g. `t = 1.200e-02 s  step 120  42.0 %  ETA 00:01:13`.
  /// `elapsed` is the wall time since start (public for tests).
  std::string line(double time, long step, double elapsed_seconds) const;

 private:
  double start_time_, end_time_;
  bool enabled_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

}  // namespace shellflow
