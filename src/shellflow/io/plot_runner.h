#pragma once
// The plots of a run, drawn by one Python process: tools/plot_run.py imports matplotlib once
// and calls main(argv) of each tools/plot_*.py job in turn (docs/output.md). A plot is a
// convenience: when Python, matplotlib or a script fails, a warning says so and the run's
// numerical output stands; nothing here throws for a failed plot.
#include <filesystem>
#include <string>
#include <vector>

namespace shellflow::io {

class PlotRunner {
 public:
  /// `python`: the interpreter to run (run/output_dir.cpp passes the SHELLFLOW_PYTHON it is
  /// built with). `output_to_stderr`: the scripts' stdout goes to stderr (for commands whose
  /// stdout is JSON).
  explicit PlotRunner(std::filesystem::path python, bool output_to_stderr = false);

  /// Queues `tools/<script> args...` (e.g. "plot_probes.py", {"out/probes.csv", "-o",
  /// "out/probes.png"}). A script that is not in the source tree's tools/ is skipped with a
  /// warning ("plot skipped: ... not found").
  void add(const std::string& script, std::vector<std::string> args);

  /// Runs every queued job in one `python tools/plot_run.py --job SCRIPT N ARGS...` process
  /// (posix_spawn with an argument vector: no shell), waits for it and empties the queue.
  /// Returns true when every plot was drawn (or none was queued); otherwise logs a warning
  /// ("plot failed ...; the numerical output is complete") and returns false.
  bool run();

  std::size_t size() const { return jobs_.size(); }
  /// The source tree's tools/ folder, where the scripts are looked up.
  static std::filesystem::path tools_dir();

 private:
  struct Job {
    std::string script;
    std::vector<std::string> args;
  };
  std::filesystem::path python_;
  bool output_to_stderr_ = false;
  std::vector<Job> jobs_;
};

}  // namespace shellflow::io
