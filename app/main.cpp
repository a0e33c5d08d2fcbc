// shellflow: thin elastic shells in compressible gas flow.
//
//   shellflow mesh  cases/panel_flutter/clamped_clamped.yaml [-o OUTDIR] [--json]
//   shellflow check cases/panel_flutter/clamped_clamped.yaml
//   shellflow run   cases/panel_flutter/clamped_clamped.yaml [-o OUTDIR] [--stop-after N]
//                   [--stop-at-wall S] [--restart OUTDIR[/checkpoint_NNNNNN.ckpt]]
//   shellflow flutter cases/panel_flutter/clamped_clamped_piston.yaml [--parameter mach] [--json]
//   shellflow partition cases/panel_flutter/clamped_clamped.yaml --parts N [-o OUTDIR]
//   shellflow study cases/panel_flutter/clamped_clamped_piston.yaml [-j N] [--json]
//
// Every error the user can fix is printed as one line `shellflow: error: ...` and the
// exit code is 1 (2 for a bad command line); a run the physics stopped (a SolverError: Newton
// gave up, a negative density, an inverted element) exits with 4; a run stopped with a
// checkpoint (--stop-after, --stop-at-wall, SIGINT/SIGTERM/SIGUSR1) exits with 75.
#include <fmt/format.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <string_view>
#include <vector>

#include "commands.h"
#include "shellflow/core/error.h"
#include "shellflow/core/output_file.h"
#include "shellflow/core/version.h"
#include "shellflow/fluid/residual.h"
#include "shellflow/mpi/communicator.h"
#include "shellflow/run/run_control.h"

namespace {

/// The rank count as OpenMPI's or MPICH's launcher sets it in the environment (1 without one).
int launcher_ranks() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* value = std::getenv(name)) return int(std::clamp(std::atol(value), 0L, 1L << 24));
  return 1;
}

/// Why a process the environment calls one of `launched` MPI ranks cannot go on ("" when it
/// can): MPI disagrees (the variables are left over, no launcher started it), or the command
/// does not run on ranks (said by rank 0; the other ranks get "" and a world of size > 1).
std::string check_launch(int launched, bool is_run) {
  const shellflow::mpi::Communicator& world = shellflow::mpi::Communicator::world();
  if (world.size() != launched)
    return fmt::format(
        "the environment says this process is one of {} MPI ranks (OMPI_COMM_WORLD_SIZE or PMI_SIZE) but MPI "
        "started {}: no launcher started it; start it with 'mpirun -np {}', or unset those variables to run it as "
        "one process",
        launched, world.size(), launched);
  if (!is_run && world.rank() == 0)
    return fmt::format(
        "started as {} MPI ranks; only 'shellflow run' runs on several ranks (docs/parallel.md): run this command "
        "without mpirun",
        launched);
  return {};
}

/// How a command ended: its exit code and, for an error, the line to print.
struct Outcome {
  int code = 0;
  std::string message = {};
  bool internal = false;  ///< not an error the user can fix (exit code 3)
};

/// Runs the parsed subcommand; its exit code, or the error it ended with.
Outcome run_command(const std::vector<shellflow::app::Command>& commands) {
  using namespace shellflow;
  try {
    // A bad SHELLFLOW_SIMD is refused before anything is read or meshed.
    spdlog::debug("element pass: {}", fluid::to_string(fluid::simd_path()));
    for (const app::Command& command : commands)
      if (command.app->parsed()) return {command.run(), {}, false};
  } catch (const SolverError& e) {
    return {app::kSolverFailedExitCode, e.what(), false};
  } catch (const Error& e) {
    return {1, e.what(), false};
  } catch (const std::exception& e) {
    return {3, e.what(), true};
  }
  return {};
}

}  // namespace

int main(int argc, char** argv) {
  using namespace shellflow;
  (void)run::process_start();  // --stop-at-wall counts from here
  // Log to stderr so that stdout carries only results (tables, JSON).
  auto logger = spdlog::stderr_color_mt("shellflow");
  spdlog::set_default_logger(logger);
  spdlog::set_pattern("[%H:%M:%S] %^%l%$: %v");

  CLI::App cli{
      "shellflow: geometrically nonlinear shells in compressible gas flow "
      "(positional shell FEM, ALE Taylor-Galerkin flow, space-mesh fluid mesh motion)",
      "shellflow"};
  cli.set_version_flag("--version", std::string("shellflow ") + shellflow::version);
  cli.require_subcommand(1);
  cli.footer(
      "Environment: OMP_NUM_THREADS (threads of a run; the results are the same bits on any count), "
      "SHELLFLOW_SPIN_US=microseconds (how long an idle thread spins before it sleeps; default 20), "
      "SHELLFLOW_SIMD=auto|sse2|avx2|avx2-fma|avx512 (instruction set of the flow's element "
      "pass; default auto: the best the CPU has; sse2 is the reference, avx2 gives its bits, "
      "avx2-fma and avx512 round differently), SHELLFLOW_GEO_TIMEOUT=seconds (the most Gmsh may take to read a "
      ".geo; default 120). An output folder is used by one process at a time (.shellflow.lock) and no file is "
      "written through a symbolic or hard link there (docs/output.md). Exit codes: 0 done; 1 an error "
      "(one line 'shellflow: error: ...'); 2 a bad command line; 3 an internal error; 4 a run the physics "
      "stopped (Newton gave up, a negative density, an inverted element); 75 stopped with a checkpoint "
      "(--stop-after, --stop-at-wall, SIGINT, SIGTERM, SIGUSR1): continue with --restart. Under mpirun "
      "stop a run with SIGUSR1 to mpirun (it passes it on; SIGINT/SIGTERM make mpirun kill the ranks a second "
      "later and exit 1; docs/parallel.md).");
  cli.fallthrough();  // -v/-q also after the subcommand
  bool verbose = false, quiet = false;
  cli.add_flag("-v,--verbose", verbose, "Print debug messages (and Gmsh's progress)");
  cli.add_flag("-q,--quiet", quiet, "Print warnings and errors only");

  app::CommonOptions options;
  const std::vector<app::Command> commands{
      app::add_run_command(cli, options),       app::add_mesh_command(cli, options),
      app::add_check_command(cli, options),     app::add_flutter_command(cli, options),
      app::add_partition_command(cli, options), app::add_study_command(cli, options),
  };
  const CLI::App* run = commands.front().app;  // run first

  CLI11_PARSE(cli, argc, argv);
  spdlog::set_level(verbose ? spdlog::level::debug : quiet ? spdlog::level::warn : spdlog::level::info);
  // Started by mpirun with several ranks (the launcher says so in the environment): `run`
  // distributes a flow over them (docs/parallel.md); MPI is started for that only, so a plain
  // `shellflow run` is one process without MPI. The rank and the rank count are MPI's. Rank 0
  // alone logs, prints errors and writes the output folder (core/output_file.h).
  const int launched_ranks = launcher_ranks();
  if (*run) run::arm_stop_signals();  // a signal during set-up stops the run, it does not kill it
  bool print_errors = true;
  if (launched_ranks > 1) {
    if (const std::string why = check_launch(launched_ranks, bool(*run)); !why.empty()) {
      std::fprintf(stderr, "shellflow: error: %s\n", why.c_str());
      return 1;
    }
    if (!*run) return 1;  // rank 0 said why
    options.ranks = &mpi::Communicator::world();
    if (options.ranks->rank() != 0) {
      set_process_writes_files(false);
      spdlog::set_level(spdlog::level::off);
      print_errors = false;
    }
  }
  const Outcome outcome = run_command(commands);
  // Rank 0 may still have its error to say when another rank has left and mpirun ends the job.
  run::quiet_stop_signals();
  if (outcome.code == 0 || outcome.code == app::kStoppedExitCode) return outcome.code;
  // An error on ranks: when every rank leaves with it (the errors they agree on), rank 0 says
  // it; when a rank is left waiting for this one (an error only it saw), this rank says it and
  // ends the job, so that no rank hangs.
  if (options.ranks && !options.ranks->all_leave_within(10.0)) {
    std::fprintf(stderr, "shellflow: %s: rank %d: %s\n", outcome.internal ? "internal error" : "error",
                 options.ranks->rank(), outcome.message.c_str());
    options.ranks->abort_job(outcome.code);
  }
  if (print_errors)
    std::fprintf(stderr, "shellflow: %s: %s\n", outcome.internal ? "internal error" : "error", outcome.message.c_str());
  return outcome.code;
}
