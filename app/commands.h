#pragma once
// The subcommands of `shellflow`. Each returns the process exit code and throws
// shellflow::Error for anything the user must fix (caught and printed once in main).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace shellflow::app {

struct CommonOptions {
  std::filesystem::path case_file;
  std::optional<std::filesystem::path> output_dir;  ///< -o; default: the case's output.directory
  bool plot = true;                                 ///< make the PNG plot at the end
};

int run_command(const CommonOptions& options);
int mesh_command(const CommonOptions& options, bool json);
int check_command(const CommonOptions& options);

/// Runs tools/<script> with Debian's Python on the argument vector `args` (no shell is
/// involved); logs a warning (not an error) if the plot cannot be made, since the numerical
/// output is already written. `output_to_stderr`: the script's stdout goes to our stderr
/// (when stdout carries machine-readable output, e.g. `mesh --json`).
void make_plot(const std::string& script, const std::vector<std::string>& args, bool output_to_stderr = false);

}  // namespace shellflow::app
