#include "shell_run.h"

#include "field_writers.h"
#include "time_loop.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <tuple>
#include <utility>

#include "shellflow/core/error.h"
#include "shellflow/core/progress.h"
#include "shellflow/io/mesh_output.h"
#include "shellflow/io/pvd_writer.h"
#include "shellflow/shell/newmark_solver.h"
#include "shellflow/shell/shell_model.h"
#include "shellflow/shell/static_solver.h"
#include "shellflow/setup/shell_setup.h"

namespace shellflow::app {
void run_shell(const io::Case& c, const io::CaseMeshes& meshes, io::ProbeSet& probes,
               std::span<const io::FieldView> initial_fields, const std::filesystem::path& outdir) {
  const io::ShellSection& s = *c.shell;
  const io::ShellAnalysis& analysis = *s.analysis;
  const mesh::Mesh& mesh = *meshes.shell;
  shell::ShellModel model = setup::build_shell_model(s, mesh);
  const Index n = mesh.num_nodes();
  ShellWriter writer(model, outdir, c.output.shell_stress);

  // Records probes and (every output.every steps) fields of state u, v at time / level t.
  auto record = [&](long step, double t, const Eigen::VectorXd& u, const Eigen::VectorXd* v,
                    bool write_fields) {
    std::vector<io::FieldView> fields;
    for (const auto& f : initial_fields)
      if (f.mesh != "shell") fields.push_back(f);
    const auto views = writer.update(u, v);
    fields.insert(fields.end(), views.begin(), views.end());
    probes.record(t, fields);
    if (write_fields) writer.write(step, t, u);
  };

  if (analysis.type == io::ShellAnalysisType::static_load) {
    shell::NewtonOptions newton;
    newton.modified = analysis.modified_newton;
    shell::StaticSolver solver(model, newton);
    record(0, 0.0, solver.displacement(), nullptr, true);
    long step = 0;
    auto on_level = [&](const shell::LoadStep& level, bool last) {
      ++step;
      spdlog::info("load factor {:.6g}: converged in {} Newton iterations", level.load_factor,
                   level.iterations);
      record(step, level.load_factor, solver.displacement(), nullptr,
             step % c.output.every == 0 || last);
    };
    try {
      switch (analysis.control) {
        case io::PathControl::load:
          solver.run(analysis.steps, 1.0, [&](const shell::LoadStep& level) {
            on_level(level, level.load_factor >= 1.0 - 1e-12);
          });
          break;
        case io::PathControl::displacement: {
          shell::ControlledDisplacement control;
          control.node = analysis.controlled_node;
          control.group = analysis.controlled_group;
          control.component = analysis.controlled_component;
          if (control.node >= n) {
            throw_at(analysis.where, fmt::format("controlled node {} does not exist: the shell "
                                                 "mesh has nodes 0 to {}",
                                                 control.node, n - 1));
          }
          long level_count = 0;
          solver.run_displacement_control(control, analysis.steps, analysis.final_displacement,
                                          [&](const shell::LoadStep& level) {
                                            on_level(level, ++level_count == analysis.steps);
                                          });
          break;
        }
        case io::PathControl::arc_length: {
          shell::ArcLengthOptions options;
          options.initial_load_increment = analysis.initial_load_increment;
          long level_count = 0;
          const auto levels =
              solver.run_arc_length(analysis.steps, options, [&](const shell::LoadStep& level) {
                const bool done = level.load_factor >= analysis.final_load_factor;
                on_level(level, done || ++level_count == analysis.steps);
                return !done;
              });
          if (levels.empty() || levels.back().load_factor < analysis.final_load_factor) {
            spdlog::warn(
                "arc length: load factor {:.6g} after {} steps, short of the final "
                "load factor {}; raise analysis.steps",
                levels.empty() ? 0.0 : levels.back().load_factor, levels.size(),
                analysis.final_load_factor);
          }
          break;
        }
      }
    } catch (const SolverError& e) {
      record(step + 1, solver.load_factor(), solver.displacement(), nullptr, true);
      throw SolverError(fmt::format("{}; the last converged state (load factor {:.6g}) is in {}",
                                    e.what(), solver.load_factor(), outdir.string()));
    }
    return;
  }

  const TimeFunction load_function = analysis.load_function;
  shell::NewmarkSolver solver(model, setup::newmark_options(analysis), [&](double t) { return load_function.value(t); });
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.num_dofs());
  solver.set_initial_state(zero, zero);
  record(0, 0.0, solver.displacement(), &solver.velocity(), true);
  const double dt = c.time->step;
  const auto steps = static_cast<long>(std::llround(c.time->end / dt));
  long newton_total = 0;
  run_time_loop(
      {steps, c.output.every, c.time->end, outdir, {}},
      [&](long step) {
        const int iterations = solver.advance(dt);
        newton_total += iterations;
        spdlog::debug("step {} t = {:.6g} s: {} Newton iterations", step, solver.time(), iterations);
        return solver.time();
      },
      [&](long step, bool fields) { record(step, solver.time(), solver.displacement(), &solver.velocity(), fields); },
      [&] { return solver.time(); });
  spdlog::info("shell dynamics: {} steps to t = {:.6g} s, {} Newton iterations, {} factorisations",
               steps, solver.time(), newton_total, solver.matrix_factorizations());
}

}  // namespace shellflow::app
