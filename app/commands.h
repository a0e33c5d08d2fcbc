#pragma once
// The subcommands of `shellflow`. Each returns the process exit code and throws
// shellflow::Error for anything the user must fix (caught and printed once in main).
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "run_control.h"
#include "shellflow/coupling/linear_flutter.h"

namespace shellflow::app {

struct CommonOptions {
  std::filesystem::path case_file;
  std::optional<std::filesystem::path> output_dir;  ///< -o; default: the case's output.directory
  bool plot = true;                                 ///< make the PNG plot at the end
  std::vector<std::string> overrides;               ///< --set KEY=VALUE, applied to the case file
};

int run_command(const CommonOptions& options, const StopOptions& stop = {});

/// `shellflow flutter`: the linear flutter analysis (coupling/linear_flutter.h).
struct FlutterOptions {
  coupling::FlutterParameter parameter = coupling::FlutterParameter::lambda;
  std::optional<std::pair<double, double>> range;  ///< default: lambda [0, max(1000, 2 lambda_case)], Mach [1.2, max(3, 2 M)]
  int points = 50;
  int modes = 24;          ///< in-vacuo modes of the basis
  bool direct = false;     ///< the full system instead of the modal basis
  bool no_aerodynamic_damping = false;  ///< mu/M -> 0
  bool json = false;       ///< print the summary on stdout
};
int flutter_command(const CommonOptions& common, const FlutterOptions& options);

/// `shellflow study`: the case's `study` section (io::StudySection), one run per point.
struct StudyOptions {
  int jobs = 1;       ///< runs at once (each its own process)
  bool json = false;  ///< print study.json on stdout
};
int study_command(const CommonOptions& common, const StudyOptions& options);
int mesh_command(const CommonOptions& options, bool json);
int check_command(const CommonOptions& options);

/// Runs tools/<script> with Debian's Python on the argument vector `args` (no shell is
/// involved); logs a warning (not an error) if the plot cannot be made, since the numerical
/// output is already written. `output_to_stderr`: the script's stdout goes to our stderr
/// (when stdout carries machine-readable output, e.g. `mesh --json`).
void make_plot(const std::string& script, const std::vector<std::string>& args, bool output_to_stderr = false);

}  // namespace shellflow::app
