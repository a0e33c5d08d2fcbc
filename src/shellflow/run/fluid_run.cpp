// A flow on a fixed or prescribed moving mesh.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <optional>

#include "shellflow/run/flow_ranks.h"
#include "shellflow/run/fluid_pieces.h"
#include "shellflow/run/run_kinds.h"
#include "shellflow/run/time_loop.h"
#include "shellflow/setup/fluid_setup.h"

namespace shellflow::run {
namespace {

/// Moves the mesh of `flow` to its prescribed position at t + dt with w = (x^{n+1} - x^n) / dt
/// and steps the flow there.
void step_moving_mesh(const io::FluidMeshMotion& motion, setup::Flow& flow, std::span<const Vec3> initial,
                      std::vector<Vec3>& next, double dt) {
  fluid::FluidModel& model = *flow.model;
  std::vector<Vec3>& w = *flow.mesh_velocity;
  const double t_next = model.time() + dt;
  const auto x = model.positions();
  for (std::size_t a = 0; a < initial.size(); ++a) {
    for (std::size_t d = 0; d < 3; ++d)
      next[a][Eigen::Index(d)] = initial[a][Eigen::Index(d)] + motion.displacement[d](initial[a], t_next);
    w[a] = (next[a] - x[a]) / dt;
  }
  model.step(dt, next, w);
}

}  // namespace

void run_fluid(const RunContext& run) {
  const io::FluidSection& section = *run.c.fluid;
  const io::FluidAnalysis& analysis = *section.analysis;
  // 1. The flow (renumbered mesh, boundary conditions, initial state) and its output; on ranks,
  // the rank's part of it, its piece of the frames and the probes' values from their owners.
  const mpi::Communicator* ranks = run.ranks;
  setup::Flow flow;
  std::optional<FlowRanks> distribution;
  std::optional<FluidPieces> pieces;
  mpi::on_every_rank(ranks, [&] {
    flow = ranks ? setup::build_flow(section, *run.meshes.fluid, ranks->rank(), ranks->size())
                 : setup::build_flow(section, *run.meshes.fluid);
    if (!ranks) return;
    distribution.emplace(*ranks, *flow.part);
    distribution->attach(*flow.model);
    pieces.emplace(distribution->pieces(*flow.model, flow.new_index, run.recorder.probes()));
  });
  fluid::FluidModel& model = *flow.model;
  std::optional<FluidOutput> output;
  if (pieces)
    output.emplace(*run.meshes.fluid, *pieces, model, run.outdir, run.control.output_mode());
  else
    output.emplace(*run.meshes.fluid, flow.new_index, model, run.outdir, run.control.output_mode());
  run.recorder.add(*output);
  // 2. One step: local time steps to a steady state, or a global CFL step on a fixed or
  // moving mesh.
  const bool steady = analysis.type == io::FluidAnalysisType::steady;
  const io::FluidMeshMotion* motion = section.mesh_motion ? &*section.mesh_motion : nullptr;
  const std::vector<Vec3> initial(model.positions().begin(), model.positions().end());
  std::vector<Vec3> next(motion ? initial.size() : 0);
  double first_density_rate = 0.0;
  bool converged = false;
  const auto advance = [&](long step) {
    if (steady) {
      model.step_local(analysis.cfl);
      if (step == 1) first_density_rate = model.density_rate();
      converged = analysis.residual_drop && model.density_rate() <= *analysis.residual_drop * first_density_rate;
      return static_cast<double>(step);
    }
    const double dt = std::min(model.stable_dt(analysis.cfl), run.c.time->end - model.time());
    if (motion)
      step_moving_mesh(*motion, flow, initial, next, dt);
    else
      model.step(dt);
    return model.time();
  };
  // 3. The steps.
  const auto more = [&](long completed) {
    return steady ? completed < analysis.steps && !converged : model.time() < run.c.time->end * (1 - 1e-12);
  };
  TimeStepping stepping;
  stepping.kind = "flow";
  stepping.loop = {0, run.c.output.every, steady ? double(analysis.steps) : run.c.time->end, run.outdir, more};
  stepping.advance = advance;
  stepping.time = [&] { return model.time(); };
  // On ranks the checkpoint holds the whole mesh's state, as one process writes it: it restarts
  // on any number of ranks.
  stepping.save = [&](ArchiveWriter& out) {
    if (distribution)
      distribution->save(model, out);
    else
      model.save(out);
    out.put(first_density_rate);
    out.put(converged);
  };
  stepping.restore = [&](ArchiveReader& in) {
    if (distribution)
      distribution->restore(model, in);
    else
      model.restore(in);
    first_density_rate = in.get<double>();
    converged = in.get<bool>();
  };
  const long step = step_in_time(run.control, run.recorder, stepping);
  // 4. The summary.
  if (!steady) {
    spdlog::info("flow: {} steps to t = {:.6g} s", step, model.time());
    return;
  }
  spdlog::info("steady flow: {} local steps, density rate {:.3e} ({:.2e} of the first step's)", step,
               model.density_rate(), model.density_rate() / std::max(first_density_rate, 1e-300));
  if (analysis.residual_drop && !converged)
    spdlog::warn(
        "steady flow: the density rate did not drop to {:g} of its first value in {} steps; raise "
        "analysis.steps (or check the case)",
        *analysis.residual_drop, analysis.steps);
}

}  // namespace shellflow::run
