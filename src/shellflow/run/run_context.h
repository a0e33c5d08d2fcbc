#pragma once
// What every kind of run gets from run_case (run.h): the case, its meshes, the output folder,
// the checkpoint/stop/restart control, the recorder of probes and frames, and the list of
// plots drawn when the run ends.
#include <filesystem>

#include "shellflow/io/case.h"
#include "shellflow/io/case_meshes.h"
#include "shellflow/mpi/communicator.h"
#include "shellflow/run/output_dir.h"
#include "shellflow/run/recorder.h"
#include "shellflow/run/run_control.h"

namespace shellflow::run {

struct RunContext {
  const io::Case& c;
  const io::CaseMeshes& meshes;
  std::filesystem::path outdir;
  RunControl& control;
  Recorder& recorder;
  PlotJobs& plots;
  /// The ranks of a distributed run (every rank runs the same code; rank 0 alone writes the
  /// output folder, core/output_file.h); null in one process.
  const mpi::Communicator* ranks = nullptr;
};

}  // namespace shellflow::run
