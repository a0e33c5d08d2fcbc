#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "commands.h"
#include "shellflow/io/case.h"

namespace shellflow::app {
/// The case file of the command line, with its --set overrides applied.
io::Case read_case(const CommonOptions& options);
/// The output directory of a run (-o, else the case's output.directory), created.
std::filesystem::path prepare_output_dir(const io::Case& c, const CommonOptions& options);
/// Whether `name` is a file `shellflow run` writes: `<mesh>_NNNNNN.vtu`, `<mesh>.pvd`,
/// `shell_mode_NN.vtu`, probes.csv, coupling.csv, response.json, the plots, checkpoint_NNNNNN.ckpt
/// ... (docs/output.md),
/// or the `.tmp` leftover of one.
bool is_run_output_name(const std::string& name);
/// Removes the files of an earlier run from `dir` (only regular files whose names
/// is_run_output_name accepts, directly in `dir`: no other file, no folder) so that a new run
/// does not leave the old frames of a longer run in its series; logs how many. Returns that.
std::size_t remove_previous_run_output(const std::filesystem::path& dir);
/// The arguments of tools/plot_probes.py for a run's probes.csv: the abscissa's label (a static
/// shell run's `time` column is its load factor) and each probe's reference curve.
std::vector<std::string> probe_plot_arguments(const io::Case& c, const std::filesystem::path& outdir);
}  // namespace shellflow::app
