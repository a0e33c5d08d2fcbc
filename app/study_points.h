#pragma once
// The points of `shellflow study`: every value of the parameter is a `shellflow run` of the
// case with --set overrides, in its own folder (points/<parameter>_<value>/), in its own
// process, up to --jobs at once. A point whose folder holds a finished point.json of the same
// settings is not rerun; a run stopped with a checkpoint continues from it. A point run ends
// when the study dies (SIGTERM: it stops with a checkpoint). Only a result of the physics is
// recorded: a run that failed otherwise (exit code not 0, 4 or 75) is rerun by the next study.
#include <csignal>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "shellflow/io/case.h"

namespace shellflow::app::study {

/// What a point run gave.
struct Point {
  double value = 0.0;
  bool ok = false;
  /// Failed for a reason other than the physics (exit code other than 0, 4 and 75: a lock,
  /// a kill, an I/O or input error): not recorded in point.json, the next study reruns it.
  bool rerun = false;
  std::string message;  ///< failed: the run's error line
  double growth_rate = std::nan(""), growth_rate_error = std::nan(""), frequency_hz = std::nan("");
  bool saturated = false;
  double lco_amplitude = std::nan(""), lco_frequency_hz = std::nan("");
  std::filesystem::path dir;
};

/// Every --set of a point's run: the command line's, the study's `set`, then the parameter's.
std::vector<std::string> run_overrides(const io::Case& c, const CommonOptions& common, double value);

class PointRunner {
 public:
  PointRunner(const io::Case& c, const CommonOptions& common, std::filesystem::path root, int jobs);
  ~PointRunner();
  PointRunner(const PointRunner&) = delete;
  PointRunner& operator=(const PointRunner&) = delete;
  /// Runs the values not yet finished, `jobs` at a time; returns every value's point.
  std::vector<Point> run(const std::vector<double>& values);
  /// Whether a run stopped with a checkpoint (a signal): the study stops too.
  bool interrupted() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// SIGINT/SIGTERM stop a study (its runs get the signal too and stop with checkpoints) while
/// an object of this type lives; the previous handlers come back with its end.
class StudySignals {
 public:
  StudySignals();
  ~StudySignals();
  StudySignals(const StudySignals&) = delete;
  StudySignals& operator=(const StudySignals&) = delete;
  /// Whether a stop signal came.
  static bool received();

 private:
  struct sigaction old_int_ {
  }, old_term_{};
};

}  // namespace shellflow::app::study
