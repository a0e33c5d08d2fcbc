#include "shellflow/core/progress.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace shellflow {

Progress::Progress(double start_time, double end_time, bool enabled)
    : start_time_(start_time),
      end_time_(end_time),
      enabled_(enabled),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

namespace {
/// Started by an MPI launcher: the ranks' output goes through it, and OpenMPI gives them a
/// terminal even when its own output is a file, so the line would fill a batch job's log.
bool under_mpi_launcher() { return std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE"); }
}  // namespace

// On a terminal, in a process not started by an MPI launcher.
Progress::Progress(double start_time, double end_time)
    : Progress(start_time, end_time, isatty(STDOUT_FILENO) != 0 && !under_mpi_launcher()) {}

Progress::~Progress() { finish(); }

std::string Progress::line(double time, long step, double elapsed) const {
  const double span = end_time_ - start_time_;
  const double fraction = span > 0 ? std::clamp((time - start_time_) / span, 0.0, 1.0) : 1.0;
  std::string eta = "--:--:--";
  if (fraction > 0.0 && elapsed > 0.0) {
    const auto remaining = static_cast<long>(std::lround(elapsed * (1.0 - fraction) / fraction));
    eta = fmt::format("{:02}:{:02}:{:02}", remaining / 3600, (remaining / 60) % 60, remaining % 60);
  }
  return fmt::format("t = {:.3e} s  step {}  {:5.1f} %  ETA {}", time, step, 100.0 * fraction, eta);
}

void Progress::update(double time, long step) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (drawn_ && now - last_draw_ < std::chrono::milliseconds(200)) return;
  last_draw_ = now;
  drawn_ = true;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  std::fprintf(stdout, "\r%s\x1b[K", line(time, step, elapsed).c_str());
  std::fflush(stdout);
}

void Progress::finish() {
  if (enabled_ && drawn_) {
    std::fputc('\n', stdout);
    std::fflush(stdout);
  }
  drawn_ = false;
}

}  // namespace shellflow
