#pragma once
// The kinds of run behind run_case (run.h), one function each. Each builds its solvers
// through setup/, hands the outputs of the meshes it moves to run.recorder and, when it steps
// in time, hands itself to the one loop (time_loop.h: step_in_time). A SolverError (Newton
// fails for good, a negative pressure, an inverted element) stops a run after its last valid
// state was written.
#include <optional>
#include <string>

#include "shellflow/run/flow_ranks.h"
#include "shellflow/run/fluid_pieces.h"
#include "shellflow/run/run_context.h"
#include "shellflow/setup/coupled_setup.h"

namespace shellflow::run {

/// The case's shell alone (shell_run.cpp): static load stepping (probes.csv rows are load
/// levels, its `time` column holds the load factor), Newmark dynamics from 0 to time.end, or
/// the natural frequencies and modes (modes.csv, modes.json, shell_modes.vtu, modes.pvd).
void run_shell(const RunContext& run);

/// A flow on a fixed or prescribed moving mesh (fluid_run.cpp): transient (global CFL step to
/// time.end) or steady (local time steps), from the free stream, a Riemann problem or a
/// given initial state.
void run_fluid(const RunContext& run);

/// A prescribed boundary motion moving the fluid mesh, no flow (motion_run.cpp): the paper's
/// mesh-motion tests; motion_quality.csv per step.
void run_mesh_motion(const RunContext& run);

/// Shell and flow (or piston theory, or only the fluid mesh) together (coupled_run.cpp):
/// coupling.csv, mesh_quality.csv, response.json.
void run_coupled(const RunContext& run);

/// A coupled case with coupling.identification (identification_run.cpp): the flow driven by
/// pulses of the shell's in-vacuo modes, no shell solve (coupling/forced_motion.h):
/// gaf_record.csv and gaf.json.
void run_identification(const RunContext& run);
/// The case's section digests as one string (gaf.json's `case_sections`: an identification
/// is reused for the same sections only).
std::string case_sections_digest(const io::Case& c);

/// The coupled system of a run's case; on ranks the flow on this rank's part with its halo
/// and its pieces of the fluid frames (coupled_run.cpp).
struct CoupledBuild {
  explicit CoupledBuild(const RunContext& run);
  CoupledBuild(const CoupledBuild&) = delete;
  CoupledBuild& operator=(const CoupledBuild&) = delete;
  std::optional<FlowRanks> distribution;  ///< before the system: the flow's distribution refers to it
  setup::CoupledSystem system;
  std::optional<FluidPieces> pieces;
};

}  // namespace shellflow::run
