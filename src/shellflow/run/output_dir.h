#pragma once
// The output folder of a run: its creation, the names of what a run writes there (and the
// removal of an earlier run's), and the plots drawn from it at the end.
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "shellflow/core/output_file.h"
#include "shellflow/io/case.h"
#include "shellflow/mesh/mesh.h"

namespace shellflow::run {
/// An output folder in use: its path and the lock that keeps other shellflow processes out
/// while this one writes there.
struct OutputFolder {
  std::filesystem::path path;
  OutputLock lock;
};

/// A frame file of a run: `<mesh>_NNNNNN.vtu`, or of a distributed run `<mesh>_NNNNNN.pvtu` and
/// its pieces `<mesh>_NNNNNN_p<rank>.vtu`. `entry` is the name its `.pvd` lists (the `.pvtu`
/// for a piece).
struct FrameFile {
  long step = 0;
  std::string entry;
};
std::optional<FrameFile> frame_file(std::string_view name);

/// The output directory of a run (`output_dir` = -o, else the case's output.directory),
/// created, checked and locked (open_output_dir). Refused with one line: the root folder or
/// the home folder itself; a folder that holds files named like a run's output but was never
/// a shellflow output folder (no .shellflow.lock: its files are not ours to replace).
OutputFolder prepare_output_dir(const io::Case& c, const std::optional<std::filesystem::path>& output_dir);
/// An existing output folder (a restart's): locked (OutputLock), and refused with one line
/// naming the link when a name a run writes there (*.vtu, *.pvd, *.csv, *.json, *.png, *.msh,
/// *.cache, *.ckpt, *.tmp, *.log, *.txt, points/) is a symbolic link.
OutputFolder open_output_dir(const std::filesystem::path& dir);
/// Whether `name` is a file `shellflow run` writes: `<mesh>_NNNNNN.vtu`, `<mesh>.pvd`,
/// `shell_mode_NN.vtu`, probes.csv, coupling.csv, response.json, the plots, checkpoint_NNNNNN.ckpt
/// ... (docs/output.md), or the `.tmp` leftover of one.
bool is_run_output_name(const std::string& name);
/// Removes the files of an earlier run from `dir` (only regular files whose names
/// is_run_output_name accepts, directly in `dir`: no other file, no folder) so that a new run
/// does not leave the old frames of a longer run in its series; logs how many. Returns that.
std::size_t remove_previous_run_output(const std::filesystem::path& dir);
/// The arguments of tools/plot_probes.py for a run's probes.csv: the abscissa's label (a static
/// shell run's `time` column is its load factor) and each probe's reference curve.
std::vector<std::string> probe_plot_arguments(const io::Case& c, const std::filesystem::path& outdir);

/// The contour plots of a shell that spans a surface (its second-largest extent at least a
/// fifth of its largest: a plate or a panel, not the quasi-2-D strip): `deflection.png` of
/// OUTDIR/shell.pvd at its frame of largest normal displacement (`time_series`), or
/// `modes.png` of OUTDIR/shell_modes.vtu (tools/plot_shell_field.py). Empty for a strip.
std::vector<std::string> shell_field_plot_arguments(const mesh::Mesh& shell, const std::filesystem::path& outdir,
                                                    bool time_series);

/// One plot: tools/<script> and its arguments.
struct PlotJob {
  std::string script;
  std::vector<std::string> args;
};
using PlotJobs = std::vector<PlotJob>;

/// Runs tools/<script> with Debian's Python on the argument vector `args` (io::PlotRunner: no
/// shell); logs a warning (not an error) if the plot cannot be made, since the numerical
/// output is already written. `output_to_stderr`: the script's stdout goes to our stderr
/// (when stdout carries machine-readable output, e.g. `mesh --json`).
void make_plot(const std::string& script, const std::vector<std::string>& args, bool output_to_stderr = false);
/// Draws every plot of `jobs` in one Python process (tools/plot_run.py).
void make_plots(const PlotJobs& jobs);
}  // namespace shellflow::run
