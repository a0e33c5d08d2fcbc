// A prescribed boundary motion moving the fluid mesh, no flow: the paper's mesh-motion tests.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>

#include "shellflow/core/error.h"
#include "shellflow/mesh/quality.h"
#include "shellflow/run/quality_history.h"
#include "shellflow/run/run_kinds.h"
#include "shellflow/run/time_loop.h"
#include "shellflow/setup/motion_setup.h"

namespace shellflow::run {

void run_mesh_motion(const RunContext& run) {
  const io::MotionSection& m = *run.c.motion;
  const mesh::Mesh& fluid = *run.meshes.fluid;
  // 1. The boundary motion, the mover and the moving mesh's state (positions x, velocities w).
  const auto boundary = setup::prescribed_motion(m);
  const auto mover = setup::build_mover(m, run.meshes, *boundary);
  const auto* space_mover = dynamic_cast<const motion::SpaceMeshMover*>(mover.get());
  const motion::SpaceMesh* space = space_mover ? &space_mover->space_mesh() : nullptr;
  std::vector<Vec3> x(fluid.nodes.size()), w(x.size());
  // 2. The outputs: the fluid mesh, the space mesh, the quality history with the modes'
  // amplitudes in front.
  const io::OutputMode mode = run.control.output_mode();
  FluidMeshOutput fluid_output(
      fluid, {}, fluid.nodes, [&] { return std::span<const Vec3>(x); }, [&] { return std::span<const Vec3>(w); },
      run.outdir, mode);
  run.recorder.add(fluid_output);
  std::optional<SpaceMeshOutput> space_output;
  if (space) run.recorder.add(space_output.emplace(*run.meshes.space, *space, run.outdir, mode));
  std::vector<std::string> amplitudes;
  for (std::size_t k = 0; k < m.prescribed->modes.size(); ++k) amplitudes.push_back(fmt::format("A{}", k + 1));
  QualityHistory quality(run.outdir / "motion_quality.csv", amplitudes, fluid, space, mode);
  run.recorder.add(quality.csv());
  // 3. One step: the mesh at t = step dt, its quality row; an inverted element restores the
  // state of the step before (the movers are deterministic: recompute it) and fails.
  const double dt = run.c.time->step;
  double t_state = 0.0;  // time of the state in x, w
  const auto advance = [&](long step) {
    const double t = static_cast<double>(step) * dt;
    mover->update(t, x, w);
    const mesh::QualitySummary q = quality.fluid(x);
    if (q.inverted > 0) {
      const Vec3 centre = mesh::vertex_centroid(fluid, q.worst_cell, x);
      if (step > 0) mover->update(t_state, x, w);
      throw SolverError(fmt::format(
          "t = {:.6g} s: the mesh motion inverts {} fluid element(s), the worst {} at ({:.4g}, {:.4g}, {:.4g}) m; "
          "reduce the amplitude or change motion.method / the IDW exponents",
          t, q.inverted, q.worst_cell, centre.x(), centre.y(), centre.z()));
    }
    std::vector<double> values;
    for (const auto& mode : m.prescribed->modes) values.push_back(mode.amplitude.value(t));
    quality.append(t, q, values);
    t_state = t;
    return t;
  };
  // 4. The steps; the movers are algebraic in time (the Laplace mover's warm start aside):
  // the state is the mover's.
  TimeStepping stepping;
  stepping.kind = "mesh motion";
  stepping.loop = {std::llround(run.c.time->end / dt), run.c.output.every, run.c.time->end, run.outdir, {}};
  stepping.advance = advance;
  stepping.time = [&] { return t_state; };
  stepping.save = [&](ArchiveWriter& out) { mover->save(out); };
  stepping.restore = [&](ArchiveReader& in) {
    mover->restore(in);
    t_state = static_cast<double>(run.control.first_step() - 1) * dt;
  };
  stepping.before_frame_0 = [&] {
    try {
      advance(0);
    } catch (const SolverError& e) {
      throw SolverError(
          fmt::format("{} (step 0); nothing but the initial mesh is in {}", e.what(), run.outdir.string()));
    }
  };
  const long last = step_in_time(run.control, run.recorder, stepping);
  run.plots.push_back({"plot_probes.py",
                       {(run.outdir / "motion_quality.csv").string(), "--x", "A1", "-o",
                        (run.outdir / "motion_quality.png").string()}});
  if (!run.control.stopped())
    spdlog::info("mesh motion: {} steps, fluid mesh valid throughout; quality history in {}", last,
                 (run.outdir / "motion_quality.csv").string());
}

}  // namespace shellflow::run
