#pragma once
// A mesh-motion run: the fluid mesh follows a prescribed boundary motion through the case's
// mesh mover (space mesh, direct IDW or Laplacian), with quality monitoring.
#include <filesystem>

#include "shellflow/io/case.h"
#include "shellflow/io/case_meshes.h"
#include "shellflow/io/probes.h"

namespace shellflow::app {

/// Steps from t = 0 to time.end; writes fluid_/space_NNNNNN.vtu + .pvd every output.every
/// steps, motion_quality.csv every step and the probes. Stops with SolverError (after the
/// last valid state is written) when a fluid element inverts.
void run_mesh_motion(const io::Case& c, const io::CaseMeshes& meshes, io::ProbeSet& probes,
                     std::span<const io::FieldView> initial_fields,
                     const std::filesystem::path& outdir, bool plot);

}  // namespace shellflow::app
