// The shell alone: static load stepping, Newmark dynamics, natural frequencies and modes.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "shellflow/core/error.h"
#include "shellflow/run/run_kinds.h"
#include "shellflow/run/shell_modes.h"
#include "shellflow/run/time_loop.h"
#include "shellflow/setup/shell_setup.h"
#include "shellflow/shell/newmark_solver.h"
#include "shellflow/shell/static_solver.h"

namespace shellflow::run {
namespace {

/// Load stepping by the case's path control; one probe row per load level, frames every
/// output.every levels and at the last.
void run_static(const RunContext& run, const shell::ShellModel& model) {
  const io::ShellAnalysis& analysis = *run.c.shell->analysis;
  shell::NewtonOptions newton;
  newton.modified = analysis.modified_newton;
  shell::StaticSolver solver(model, newton);
  // 1. The output of the shell's state, frame 0 of the unloaded shell.
  ShellOutput output(
      model, run.outdir, run.c.output.shell_stress, io::OutputMode::create,
      [&]() -> const Eigen::VectorXd& { return solver.displacement(); }, [] { return nullptr; });
  run.recorder.add(output);
  run.recorder.record(0, 0.0, Record::probes_and_fields);
  // 2. The levels, each recorded as it converges.
  long step = 0, written = 0;
  const auto on_level = [&](const shell::LoadStep& level, bool last) {
    ++step;
    spdlog::info("load factor {:.6g}: converged in {} Newton iterations", level.load_factor, level.iterations);
    const bool frame = step % run.c.output.every == 0 || last;
    run.recorder.record(step, level.load_factor, frame ? Record::probes_and_fields : Record::probes);
    if (frame) written = step;
  };
  try {
    switch (analysis.control) {
      case io::PathControl::load:
        solver.run(analysis.steps, 1.0,
                   [&](const shell::LoadStep& level) { on_level(level, level.load_factor >= 1.0 - 1e-12); });
        break;
      case io::PathControl::displacement: {
        shell::ControlledDisplacement control{.node = analysis.controlled_node,
                                              .group = analysis.controlled_group,
                                              .component = analysis.controlled_component};
        if (control.node >= model.num_nodes())
          throw_at(analysis.where, fmt::format("controlled node {} does not exist: the shell mesh has nodes 0 to {}",
                                               control.node, model.num_nodes() - 1));
        long levels = 0;
        solver.run_displacement_control(
            control, analysis.steps, analysis.final_displacement,
            [&](const shell::LoadStep& level) { on_level(level, ++levels == analysis.steps); });
        break;
      }
      case io::PathControl::arc_length: {
        shell::ArcLengthOptions options;
        options.initial_load_increment = analysis.initial_load_increment;
        long count = 0;
        const auto levels = solver.run_arc_length(analysis.steps, options, [&](const shell::LoadStep& level) {
          const bool done = level.load_factor >= analysis.final_load_factor;
          on_level(level, done || ++count == analysis.steps);
          return !done;
        });
        if (levels.empty() || levels.back().load_factor < analysis.final_load_factor)
          spdlog::warn(
              "arc length: load factor {:.6g} after {} steps, short of the final load factor {}; raise "
              "analysis.steps",
              levels.empty() ? 0.0 : levels.back().load_factor, levels.size(), analysis.final_load_factor);
        break;
      }
    }
  } catch (const SolverError& e) {
    // 3. The solver is back at the last converged level (`step`), whose probe row is written:
    // only its frame, unless it has one (no second frame or row of the same state).
    if (written != step) run.recorder.record(step, solver.load_factor(), Record::fields);
    throw SolverError(fmt::format("{}; the last converged state (load factor {:.6g}) is in {}", e.what(),
                                  solver.load_factor(), run.outdir.string()));
  }
}

/// Newmark (or midpoint) steps from rest to time.end.
void run_dynamic(const RunContext& run, const shell::ShellModel& model) {
  const io::ShellAnalysis& analysis = *run.c.shell->analysis;
  // 1. The solver, from rest. A load function that is not finite at t = 0 stops the run here.
  const TimeFunction load_function = analysis.load_function;
  (void)load_function.value(0.0);
  shell::NewmarkSolver solver(model, setup::newmark_options(analysis),
                              [&](double t) { return load_function.value(t); });
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.num_dofs());
  solver.set_initial_state(zero, zero);
  // 2. Its output.
  ShellOutput output(
      model, run.outdir, run.c.output.shell_stress, run.control.output_mode(),
      [&]() -> const Eigen::VectorXd& { return solver.displacement(); }, [&] { return &solver.velocity(); });
  run.recorder.add(output);
  // 3. The steps.
  long newton_total = 0;
  const double dt = run.c.time->step;
  TimeStepping stepping;
  stepping.kind = "shell dynamics";
  stepping.loop = {std::llround(run.c.time->end / dt), run.c.output.every, run.c.time->end, run.outdir, {}};
  stepping.advance = [&](long step) {
    const int iterations = solver.advance(dt);
    newton_total += iterations;
    spdlog::debug("step {} t = {:.6g} s: {} Newton iterations", step, solver.time(), iterations);
    return solver.time();
  };
  stepping.time = [&] { return solver.time(); };
  stepping.save = [&](ArchiveWriter& out) {
    solver.save(out);
    out.put(newton_total);
  };
  stepping.restore = [&](ArchiveReader& in) {
    solver.restore(in);
    newton_total = in.get<long>();
  };
  const long last = step_in_time(run.control, run.recorder, stepping);
  spdlog::info("shell dynamics: {} steps to t = {:.6g} s, {} Newton iterations, {} factorisations", last, solver.time(),
               newton_total, solver.matrix_factorizations());
}

}  // namespace

void run_shell(const RunContext& run) {
  const io::ShellAnalysis& analysis = *run.c.shell->analysis;
  shell::ShellModel model = setup::build_shell_model(*run.c.shell, *run.meshes.shell);
  switch (analysis.type) {
    case io::ShellAnalysisType::static_load:
      run.control.not_time_stepping("a static analysis");
      run_static(run, model);
      return;
    case io::ShellAnalysisType::modal:
      run.control.not_time_stepping("a modal analysis");
      run.recorder.record(0, 0.0, Record::probes_and_fields);  // the shell at rest, like every run
      write_modes(run.c, model, run.outdir);
      if (auto args = shell_field_plot_arguments(model.mesh(), run.outdir, false); !args.empty())
        run.plots.push_back({"plot_shell_field.py", std::move(args)});
      return;
    case io::ShellAnalysisType::dynamic:
      run_dynamic(run, model);
      if (auto args = shell_field_plot_arguments(model.mesh(), run.outdir, true); !args.empty())
        run.plots.push_back({"plot_shell_field.py", std::move(args)});
      return;
  }
}

}  // namespace shellflow::run
