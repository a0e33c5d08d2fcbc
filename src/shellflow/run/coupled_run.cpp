// Shell and flow (or piston theory, or only the fluid mesh) together.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <optional>

#include "shellflow/core/error.h"
#include "shellflow/run/coupling_log.h"
#include "shellflow/run/fluid_pieces.h"
#include "shellflow/run/quality_history.h"
#include "shellflow/run/response_output.h"
#include "shellflow/run/run_kinds.h"
#include "shellflow/run/time_loop.h"
#include "shellflow/setup/coupled_setup.h"

namespace shellflow::run {
namespace {

void log_system(const io::Case& c, const setup::CoupledSystem& s) {
  const bool has_flow = c.fluid.has_value();
  const coupling::PartitionedOptions& o = s.driver->options();
  const std::string scheme =
      !has_flow      ? "no loads exchanged (the shell moves the fluid mesh)"
      : o.monolithic ? "monolithic scheme"
                     : fmt::format("{} scheme {} the linear load predictor",
                                   o.iterations.max_iterations > 1
                                       ? fmt::format("implicit staggered (up to {} iterations to {:.1e}, {})",
                                                     o.iterations.max_iterations, o.iterations.tolerance,
                                                     coupling::to_string(o.iterations.acceleration.type))
                                       : std::string("staggered"),
                                   o.predictor == coupling::LoadPredictor::linear ? "with" : "without");
  spdlog::info("coupled run: shell {} nodes / {} load points, aerodynamics '{}'{}, {}", s.shell->num_nodes(),
               s.shell->load_points().size(), s.aerodynamics->name(),
               s.flow && s.flow->flow() ? fmt::format(" ({} fluid nodes)", s.fluid_mesh->num_nodes()) : "", scheme);
  // The explicit scheme's added-mass limit (docs/coupling.md "Implicit coupling").
  const double ratio = setup::added_mass_ratio(c);
  if (!has_flow || o.monolithic || o.iterations.max_iterations > 1 || ratio == 0.0) return;
  const double limit = coupling::staggered_critical_ratio(o.predictor);
  if (ratio > 0.5 * limit)
    spdlog::warn(
        "{}: the added-mass ratio rho_inf a_inf dt / (rho_s h) = {:.3g} is {} the explicit staggered scheme's "
        "limit {:.3g}: use coupling.iterations: 20 with coupling.acceleration: iqn_ils, or a smaller time.step",
        c.file.string(), ratio, ratio > limit ? "above" : "near", limit);
}

const motion::SpaceMesh& space_mesh_of(const coupling::FlowModel& flow) {
  return dynamic_cast<const motion::SpaceMeshMover&>(flow.mover()).space_mesh();
}

/// The outputs of the meshes a coupled run moves: the shell; with a fluid mesh, the flow (or
/// the fluid mesh alone), the space mesh and the quality history.
struct CoupledOutputs {
  CoupledOutputs(const RunContext& run, const setup::CoupledSystem& s, const FluidPieces* pieces) {
    const io::OutputMode mode = run.control.output_mode();
    const shell::NewmarkSolver& solver = *s.solver;
    shell.emplace(
        *s.shell, run.outdir, run.c.output.shell_stress, mode,
        [&solver]() -> const Eigen::VectorXd& { return solver.displacement(); },
        [&solver] { return &solver.velocity(); });
    run.recorder.add(*shell);
    if (!s.flow) return;
    coupling::FlowModel& flow = *s.flow;
    if (flow.flow() && pieces)
      run.recorder.add(fluid.emplace<FluidOutput>(*run.meshes.fluid, *pieces, *flow.flow(), run.outdir, mode));
    else if (flow.flow())
      run.recorder.add(fluid.emplace<FluidOutput>(*run.meshes.fluid, s.new_index, *flow.flow(), run.outdir, mode));
    else
      run.recorder.add(fluid.emplace<FluidMeshOutput>(
          *run.meshes.fluid, s.new_index, s.fluid_mesh->nodes, [&flow] { return flow.positions(); },
          [&flow] { return flow.mesh_velocity(); }, run.outdir, mode));
    run.recorder.add(space.emplace(*run.meshes.space, space_mesh_of(flow), run.outdir, mode));
    quality.emplace(run.outdir / "mesh_quality.csv", std::vector<std::string>{}, *s.fluid_mesh, &space_mesh_of(flow),
                    mode);
    run.recorder.add(quality->csv());
  }
  std::optional<ShellOutput> shell;
  std::variant<std::monostate, FluidOutput, FluidMeshOutput> fluid;
  std::optional<SpaceMeshOutput> space;
  std::optional<QualityHistory> quality;
};

/// The coupled run as the time loop takes it: a shell step (with its fluid sub-steps) per
/// step, the driver, the response history and the totals as its state.
TimeStepping coupled_stepping(const RunContext& run, setup::CoupledSystem& s, ResponseOutput& response,
                              CouplingLog& log) {
  const double dt = run.c.time->step;
  TimeStepping stepping;
  stepping.kind = "coupled";
  stepping.loop = {std::llround(run.c.time->end / dt), run.c.output.every, run.c.time->end, run.outdir, {}};
  stepping.advance = [&s, &log, dt](long step) { return log.step(*s.driver, dt, step); };
  stepping.time = [&s] { return s.solver->time(); };
  stepping.save = [&](ArchiveWriter& out) {
    s.driver->save(out);
    response.save(out);
    log.save(out);
  };
  stepping.restore = [&](ArchiveReader& in) {
    s.driver->restore(in);
    response.restore(in);
    log.restore(in);
  };
  return stepping;
}

}  // namespace

CoupledBuild::CoupledBuild(const RunContext& run) {
  // On ranks the flow runs on the rank's part; the shell, the space mesh and the maps are
  // whole on every rank (docs/parallel.md).
  const mpi::Communicator* ranks = run.ranks;
  setup::CoupledRanks on_ranks;
  if (ranks)
    on_ranks = {ranks->rank(), ranks->size(),
                [this, ranks](const setup::FlowPart& part, fluid::FluidModel& flow, coupling::FlowModel& model) {
                  distribution.emplace(*ranks, part);
                  distribution->attach(flow, model);
                }};
  mpi::on_every_rank(ranks, [&] {
    system = setup::build_coupled_system(run.c, run.meshes, ranks ? &on_ranks : nullptr);
    if (distribution)
      pieces.emplace(distribution->pieces(*system.flow->flow(), system.new_index, run.recorder.probes()));
  });
}

void run_coupled(const RunContext& run) {
  const auto t_setup = std::chrono::steady_clock::now();
  // 1. The response probe (an unknown one fails the run at once), the coupled system.
  ResponseOutput response(run.c, run.outdir);
  CoupledBuild built(run);
  setup::CoupledSystem& s = built.system;
  std::optional<FluidPieces>& pieces = built.pieces;
  log_system(run.c, s);
  // 2. The outputs: the moving meshes, the quality and response histories, coupling.csv.
  CoupledOutputs outputs(run, s, pieces ? &*pieces : nullptr);
  CouplingLog log(run.outdir / "coupling.csv", run.control.output_mode());
  run.recorder.add(log.csv());
  run.recorder.on_sample([&](double t, std::span<const double> probes) {
    response.sample(t, probes);
    if (outputs.quality) outputs.quality->append(t, outputs.quality->fluid(s.flow->positions()));
  });
  log.add_setup_seconds(std::chrono::duration<double>(std::chrono::steady_clock::now() - t_setup).count());
  // 3. The shell steps, each with its fluid sub-steps. A run stopped by an error still writes
  // response.json, of the steps done.
  const TimeStepping stepping = coupled_stepping(run, s, response, log);
  try {
    step_in_time(run.control, run.recorder, stepping);
  } catch (...) {
    if (!run.control.restarting() || run.control.restored()) response.write_on_error();  // not for a refused restart
    throw;
  }
  // 4. The summary, response.json and the plots.
  log.summary(s.solver->time(), run.recorder.seconds());
  response.write();
  if (!run.c.probes.empty())
    run.plots.push_back({"plot_flutter.py", {(run.outdir / "probes.csv").string(), "-o", run.outdir.string()}});
  if (auto args = shell_field_plot_arguments(*run.meshes.shell, run.outdir, true); !args.empty())
    run.plots.push_back({"plot_shell_field.py", std::move(args)});
  if (outputs.quality)
    run.plots.push_back(
        {"plot_probes.py",
         {(run.outdir / "mesh_quality.csv").string(), "-o", (run.outdir / "mesh_quality.png").string()}});
}

}  // namespace shellflow::run
