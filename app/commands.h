#pragma once
// The subcommands of `shellflow`. Each command_*.cpp defines its subcommand's options
// (add_*_command) and runs it (*_command); a run returns the process exit code and throws
// shellflow::Error for anything the user must fix (caught and printed once in main).
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "shellflow/coupling/linear_flutter.h"
#include "shellflow/io/case.h"
#include "shellflow/run/output_dir.h"
#include "shellflow/run/run_control.h"

namespace CLI {
class App;
class Validator;
}  // namespace CLI

namespace shellflow::app {

struct CommonOptions {
  std::filesystem::path case_file;
  std::optional<std::filesystem::path> output_dir;  ///< -o; default: the case's output.directory
  bool plot = true;                                 ///< make the PNG plot at the end
  std::vector<std::string> overrides;               ///< --set KEY=VALUE, applied to the case file
  const mpi::Communicator* ranks = nullptr;         ///< started by mpirun with several ranks
};

/// A subcommand of the command line: its CLI11 definition and what runs it once parsed (with the
/// options it owns).
struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};
/// The case file and its --set overrides, of every subcommand.
void add_case_options(CLI::App* sub, CommonOptions& common);
/// -o and --no-plot.
void add_output_options(CLI::App* sub, CommonOptions& common);
/// A check that a number of the command line is finite (nan and inf pass CLI's own checks).
const CLI::Validator& finite_number();

Command add_run_command(CLI::App& cli, CommonOptions& common);
Command add_check_command(CLI::App& cli, CommonOptions& common);
Command add_mesh_command(CLI::App& cli, CommonOptions& common);
Command add_partition_command(CLI::App& cli, CommonOptions& common);
Command add_flutter_command(CLI::App& cli, CommonOptions& common);
Command add_study_command(CLI::App& cli, CommonOptions& common);

using run::kSolverFailedExitCode;
using run::kStoppedExitCode;
using run::make_plot;
using run::StopOptions;

/// The case file of the command line, with its --set overrides applied.
io::Case read_case(const CommonOptions& options);
/// A file's whole text (empty when it cannot be read).
std::string read_text_file(const std::filesystem::path& file);
/// Whether a run's folder holds a checkpoint to continue from (not a half-written `.tmp`).
bool has_checkpoint(const std::filesystem::path& dir);
/// The output directory of a command (-o, else the case's output.directory), created.
inline run::OutputFolder prepare_output_dir(const io::Case& c, const CommonOptions& options) {
  return run::prepare_output_dir(c, options.output_dir);
}

/// The study section and the case as a study's runs will read it at both ends of its range
/// (`check` and `study`): throws InputError with the point and the reason.
void check_study_case(const io::Case& c, const CommonOptions& common);

/// `shellflow run`: run::run_case on the case file (run/run.h).
int run_command(const CommonOptions& options, const StopOptions& stop = {});

/// `shellflow flutter`: the linear flutter analysis (coupling/linear_flutter.h).
struct FlutterOptions {
  coupling::FlutterParameter parameter = coupling::FlutterParameter::lambda;
  std::optional<std::pair<double, double>>
      range;  ///< default: lambda [0, max(1000, 2 lambda_case)], Mach [1.2, max(3, 2 M)]
  int points = 50;
  int modes = 24;                       ///< in-vacuo modes of the basis
  bool direct = false;                  ///< the full system instead of the modal basis
  bool no_aerodynamic_damping = false;  ///< mu/M -> 0
  bool json = false;                    ///< print the summary on stdout
  /// The aerodynamic model: piston theory, or identified from the case's own flow by a
  /// forced-motion run (flutter_identified.h).
  enum class Aerodynamics { piston, identified } aerodynamics = Aerodynamics::piston;
  bool modes_given = false;                 ///< --modes on the command line (identified: else the case's)
  int taps = 0;                             ///< FIR taps of the identified model; 0: auto
  double regularisation = 0.0;              ///< Tikhonov weight of the fit (relative)
  std::vector<double> identification_mach;  ///< one or two; empty: the case's
};
int flutter_command(const CommonOptions& common, const FlutterOptions& options);

/// `shellflow study`: the case's `study` section (io::StudySection), one run per point.
struct StudyOptions {
  int jobs = 1;       ///< runs at once (each its own process)
  bool json = false;  ///< print study.json on stdout
};
int study_command(const CommonOptions& common, const StudyOptions& options);
int mesh_command(const CommonOptions& options, bool json);
/// `shellflow partition`: the case's fluid mesh in `parts` parts (mesh/partition.h): a table of
/// the parts, partition.json (mesh::PartitionStats) and partition.vtu (cell field rank, point
/// field owner) in the output folder.
int partition_command(const CommonOptions& options, int parts);
int check_command(const CommonOptions& options);

}  // namespace shellflow::app
