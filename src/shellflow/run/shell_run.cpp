#include "shell_run.h"

#include "field_writers.h"
#include "time_loop.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <numbers>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include "shellflow/core/error.h"
#include "shellflow/core/progress.h"
#include "shellflow/io/mesh_output.h"
#include "shellflow/io/pvd_writer.h"
#include "shellflow/shell/modal.h"
#include "shellflow/shell/newmark_solver.h"
#include "shellflow/shell/shell_model.h"
#include "shellflow/shell/static_solver.h"
#include "shellflow/setup/shell_setup.h"

namespace shellflow::app {
namespace {

/// One mode of the modal analysis for the output: the mid-surface displacement scaled to a
/// largest nodal |Δx| of 1 (M-normalised amplitudes have units of kg^-1/2 and differ by
/// orders between modes, which makes Warp By Vector useless), its sign fixed so that the
/// largest component is positive, and the shares of its kinetic energy φ·(Mφ) on the x, y, z
/// translation rows (the rest is the directors' rotary inertia).
struct ModeShape {
  std::vector<double> displacement;
  Vec3 kinetic = Vec3::Zero();
  char direction = 'x';
};

ModeShape mode_shape(const Eigen::VectorXd& phi, const Eigen::VectorXd& M_phi, Index nodes) {
  ModeShape m;
  m.displacement = nodal_part(phi, nodes, 0);
  double largest = 0.0;
  for (const double d : m.displacement)
    if (std::abs(d) > std::abs(largest)) largest = d;
  double norm = 0.0;
  for (std::size_t k = 0; k < m.displacement.size(); k += 3)
    norm = std::max(norm, std::hypot(m.displacement[k], m.displacement[k + 1], m.displacement[k + 2]));
  const double scale = norm > 0.0 ? std::copysign(1.0 / norm, largest) : 1.0;
  for (double& d : m.displacement) d *= scale;
  for (Index n = 0; n < nodes; ++n)
    for (int i = 0; i < 3; ++i) m.kinetic(i) += phi(shell::dofs_per_node * n + i) * M_phi(shell::dofs_per_node * n + i);
  Eigen::Index axis = 0;
  m.kinetic.maxCoeff(&axis);
  m.direction = "xyz"[axis];
  return m;
}

/// Natural frequencies and modes about the undeformed shell: modes.csv, modes.json,
/// shell_modes.vtu (every mode as an array) and modes.pvd (one frame per mode).
void run_modal(const io::Case& c, const shell::ShellModel& model, io::ProbeSet& probes,
               std::span<const io::FieldView> initial_fields, const std::filesystem::path& outdir) {
  const io::ShellAnalysis& analysis = *c.shell->analysis;
  const mesh::Mesh& mesh = model.mesh();
  const Index n = mesh.num_nodes();
  probes.record(0.0, initial_fields);  // the shell at rest: one row, like every run
  if (!c.shell->loads.empty()) {
    spdlog::warn("modal analysis about the undeformed shell: its {} load(s) are not applied "
                 "(no pre-stress)",
                 c.shell->loads.size());
  }
  shell::ModalOptions options;
  options.tolerance = analysis.modal_tolerance;
  options.max_iterations = analysis.modal_max_iterations;
  const auto start = std::chrono::steady_clock::now();
  shell::ModalResult result;
  try {
    result = shell::natural_frequencies(model, analysis.modes, Eigen::VectorXd::Zero(model.num_dofs()), options);
  } catch (const SolverError& e) {
    // `FILE:LINE: shell.analysis: what`, the module's own prefix dropped.
    std::string_view what = e.what();
    if (what.starts_with("shell modal analysis: ")) what.remove_prefix(22);
    throw SolverError(analysis.where.message(what));
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  shell::SparseMatrix M = model.make_matrix();
  model.assemble_mass(M);
  std::vector<ModeShape> shapes;
  for (const Eigen::VectorXd& phi : result.modes) shapes.push_back(mode_shape(phi, M * phi, n));

  std::ofstream csv(outdir / "modes.csv");
  csv << "mode,frequency_hz,angular_frequency,direction,kinetic_x,kinetic_y,kinetic_z\n";
  std::string table = fmt::format("{:>5} {:>14} {:>16} {:>9}  kinetic energy x / y / z", "mode",
                                  "frequency [Hz]", "omega [rad/s]", "direction");
  std::string json_frequencies;
  for (std::size_t k = 0; k < shapes.size(); ++k) {
    const double f = result.frequencies[k];
    const double omega = 2.0 * std::numbers::pi * f;
    const ModeShape& m = shapes[k];
    csv << fmt::format("{},{:.10g},{:.10g},{},{:.6f},{:.6f},{:.6f}\n", k + 1, f, omega, m.direction,
                       m.kinetic.x(), m.kinetic.y(), m.kinetic.z());
    table += fmt::format("\n{:>5} {:>14.6f} {:>16.6f} {:>9}  {:.3f} / {:.3f} / {:.3f}", k + 1, f, omega,
                         m.direction, m.kinetic.x(), m.kinetic.y(), m.kinetic.z());
    json_frequencies += fmt::format("{}{:.17g}", k ? ", " : "", f);
  }
  if (!csv) throw Error(fmt::format("cannot write {}", (outdir / "modes.csv").string()));
  std::ofstream json(outdir / "modes.json");
  json << fmt::format("{{\"modes\": {}, \"frequencies_hz\": [{}], \"iterations\": {}, "
                      "\"tolerance\": {:.17g}}}\n",
                      shapes.size(), json_frequencies, result.iterations, options.tolerance);
  if (!json) throw Error(fmt::format("cannot write {}", (outdir / "modes.json").string()));

  // Both layouts of the shapes: shell_modes.vtu holds all of them side by side (compare
  // modes, pick one in Warp By Vector), modes.pvd steps through them with ParaView's time
  // controls (time = mode number; one `displacement` array, as in the dynamic runs).
  std::vector<io::VtuField> all;
  for (std::size_t k = 0; k < shapes.size(); ++k)
    all.push_back({fmt::format("mode_{:02}", k + 1), 3, shapes[k].displacement});
  io::write_mesh_vtu(outdir / "shell_modes.vtu", mesh, std::move(all));
  io::PvdWriter pvd(outdir, "modes");
  for (std::size_t k = 0; k < shapes.size(); ++k) {
    const std::string vtu = fmt::format("shell_mode_{:02}.vtu", k + 1);
    io::write_mesh_vtu(outdir / vtu, mesh, {{"displacement", 3, shapes[k].displacement}},
                       static_cast<double>(k + 1));
    pvd.add(static_cast<double>(k + 1), vtu);
  }
  spdlog::info("shell modal analysis: {} modes in {} subspace iterations ({:.2f} s)\n{}", shapes.size(),
               result.iterations, seconds, table);
  spdlog::info("wrote modes.csv, modes.json, shell_modes.vtu (arrays mode_01...), modes.pvd "
               "(shell_mode_NN.vtu)");
}

}  // namespace

void run_shell(const RunContext& run) {
  const io::Case& c = run.c;
  io::ProbeSet& probes = run.probes;
  const std::span<const io::FieldView> initial_fields = run.initial_fields;
  const std::filesystem::path& outdir = run.outdir;
  const io::ShellSection& s = *c.shell;
  const io::ShellAnalysis& analysis = *s.analysis;
  const mesh::Mesh& mesh = *run.meshes.shell;
  shell::ShellModel model = setup::build_shell_model(s, mesh);
  if (analysis.type != io::ShellAnalysisType::dynamic)
    run.control.not_time_stepping(analysis.type == io::ShellAnalysisType::modal ? "a modal analysis"
                                                                              : "a static analysis");
  if (analysis.type == io::ShellAnalysisType::modal) {
    run_modal(c, model, probes, initial_fields, outdir);  // before ShellWriter: it restarts shell.pvd
    return;
  }
  const Index n = mesh.num_nodes();
  // A load function that is not finite at t = 0 stops the run here, before ShellWriter
  // restarts shell.pvd (which then keeps its t = 0 frame).
  if (analysis.type == io::ShellAnalysisType::dynamic) (void)analysis.load_function.value(0.0);
  ShellWriter writer(model, outdir, c.output.shell_stress, run.control.output_mode());

  // Records probes and (every output.every steps) fields of state u, v at time / level t.
  long written = -1;  // the step of the last frame written
  auto record = [&](long step, double t, const Eigen::VectorXd& u, const Eigen::VectorXd* v,
                    Record what) {
    std::vector<io::FieldView> fields;
    for (const auto& f : initial_fields)
      if (f.mesh != "shell") fields.push_back(f);
    const auto views = writer.update(u, v);
    fields.insert(fields.end(), views.begin(), views.end());
    if (what != Record::fields) probes.record(t, fields);
    if (what != Record::probes) {
      writer.write(step, t, u);
      written = step;
    }
  };

  if (analysis.type == io::ShellAnalysisType::static_load) {
    shell::NewtonOptions newton;
    newton.modified = analysis.modified_newton;
    shell::StaticSolver solver(model, newton);
    record(0, 0.0, solver.displacement(), nullptr, Record::probes_and_fields);
    long step = 0;
    auto on_level = [&](const shell::LoadStep& level, bool last) {
      ++step;
      spdlog::info("load factor {:.6g}: converged in {} Newton iterations", level.load_factor,
                   level.iterations);
      record(step, level.load_factor, solver.displacement(), nullptr,
             step % c.output.every == 0 || last ? Record::probes_and_fields : Record::probes);
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
      // The solver is back at the last converged level (`step`), whose probe row is written:
      // only its frame, unless it has one (no second frame or row of the same state).
      if (written != step) record(step, solver.load_factor(), solver.displacement(), nullptr, Record::fields);
      throw SolverError(fmt::format("{}; the last converged state (load factor {:.6g}) is in {}",
                                    e.what(), solver.load_factor(), outdir.string()));
    }
    return;
  }

  const TimeFunction load_function = analysis.load_function;
  shell::NewmarkSolver solver(model, setup::newmark_options(analysis), [&](double t) { return load_function.value(t); });
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.num_dofs());
  solver.set_initial_state(zero, zero);
  long newton_total = 0;
  run.control.add_output(probes.writer());
  run.control.add_output(writer.pvd());
  run.control.set_state(
      "shell dynamics",
      [&](ArchiveWriter& out) {
        solver.save(out);
        out.put(newton_total);
      },
      [&](ArchiveReader& in) {
        solver.restore(in);
        newton_total = in.get<long>();
      });
  if (run.control.restarting())
    run.control.restore();
  else
    record(0, 0.0, solver.displacement(), &solver.velocity(), Record::probes_and_fields);
  const double dt = c.time->step;
  const auto steps = static_cast<long>(std::llround(c.time->end / dt));
  const long last = run_time_loop(
      {steps, c.output.every, c.time->end, outdir, {}},
      [&](long step) {
        const int iterations = solver.advance(dt);
        newton_total += iterations;
        spdlog::debug("step {} t = {:.6g} s: {} Newton iterations", step, solver.time(), iterations);
        return solver.time();
      },
      [&](long step, Record what) { record(step, solver.time(), solver.displacement(), &solver.velocity(), what); },
      [&] { return solver.time(); }, &run.control);
  spdlog::info("shell dynamics: {} steps to t = {:.6g} s, {} Newton iterations, {} factorisations",
               last, solver.time(), newton_total, solver.matrix_factorizations());
}

}  // namespace shellflow::app
