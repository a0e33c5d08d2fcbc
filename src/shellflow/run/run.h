#pragma once
// `shellflow run` as a library call: a case, read and checked, run into its output folder.
//
// run_case meshes the case (or, on a restart, checks the checkpoint and continues in its
// folder), sets up the recorder and the checkpoint control, runs the kind of run the case's
// sections ask for (run_kinds.h) and draws the plots. Every kind goes through the one time
// loop (time_loop.h) and records through the one recorder (recorder.h).
#include <filesystem>
#include <optional>

#include "shellflow/io/case.h"
#include "shellflow/mpi/communicator.h"
#include "shellflow/run/run_control.h"

namespace shellflow::run {

struct RunOptions {
  std::filesystem::path case_file;                  ///< for messages (how to continue a stopped run)
  std::optional<std::filesystem::path> output_dir;  ///< -o; default: the case's output.directory
  bool plot = true;                                 ///< draw the PNG plots at the end
  StopOptions stop;                                 ///< --stop-after, --stop-at-wall, --restart
  /// The MPI ranks of a distributed run (mpirun -np N with N > 1); null: one process.
  const mpi::Communicator* ranks = nullptr;
};

/// Runs case `c`. Returns 0, or kStoppedExitCode when the run stopped with a checkpoint.
/// Throws Error / InputError / SolverError (one line each) for what the user must fix.
int run_case(const io::Case& c, const RunOptions& options);

}  // namespace shellflow::run
