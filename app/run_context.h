#pragma once
// What every kind of run gets from `shellflow run` (command_run.cpp): the case, its meshes,
// the probes, the initial fields (already written as <mesh>_000000.vtu), the output folder,
// and the checkpoint/stop/restart control.
#include <filesystem>
#include <span>

#include "run_control.h"
#include "shellflow/io/case.h"
#include "shellflow/io/case_meshes.h"
#include "shellflow/io/probes.h"

namespace shellflow::app {

struct RunContext {
  const io::Case& c;
  const io::CaseMeshes& meshes;
  io::ProbeSet& probes;
  std::span<const io::FieldView> initial_fields;
  std::filesystem::path outdir;
  bool plot = true;
  RunControl& control;
};

}  // namespace shellflow::app
