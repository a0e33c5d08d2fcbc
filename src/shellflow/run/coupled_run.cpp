#include "coupled_run.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <exception>
#include <fstream>
#include <functional>
#include <optional>

#include "commands.h"
#include "field_writers.h"
#include "time_loop.h"
#include "shellflow/core/error.h"
#include "shellflow/coupling/response.h"
#include "shellflow/io/mesh_output.h"
#include "shellflow/io/probe_writer.h"
#include "shellflow/io/pvd_writer.h"
#include "shellflow/mesh/quality.h"
#include "shellflow/setup/coupled_setup.h"

namespace shellflow::app {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// The moving meshes of a coupled run: the space mesh's frames, the fluid mesh's quality
/// and, in a run without a flow, the fluid mesh's frames (displacement, mesh velocity).
class MeshWriter {
 public:
  MeshWriter(const setup::CoupledSystem& s, const io::CaseMeshes& meshes, const std::filesystem::path& outdir,
             io::OutputMode mode)
      : s_(s), meshes_(meshes), outdir_(outdir), space_pvd_(outdir, "space", mode) {
    if (!s.flow->flow()) fluid_pvd_.emplace(outdir, "fluid", mode);
    q0_ = mesh::cell_qualities(*s.fluid_mesh);
  }
  /// Fluid mesh displacement and velocity in the case's node order (for probes and VTU).
  std::vector<io::FieldView> update() {
    const auto x = s_.flow->positions();
    const auto w = s_.flow->mesh_velocity();
    const std::size_t n = s_.new_index.size();
    displacement_.resize(3 * n);
    velocity_.resize(3 * n);
    positions_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const auto k = static_cast<std::size_t>(s_.new_index[i]);
      positions_[i] = x[k];
      for (std::size_t d = 0; d < 3; ++d) {
        displacement_[3 * i + d] = x[k][Eigen::Index(d)] - s_.fluid_mesh->nodes[k][Eigen::Index(d)];
        velocity_[3 * i + d] = w[k][Eigen::Index(d)];
      }
    }
    const auto& sm = dynamic_cast<const motion::SpaceMeshMover&>(s_.flow->mover()).space_mesh();
    space_u_ = flatten(sm.displacement());
    space_v_ = flatten(sm.velocity());
    return {{"fluid", "mesh_velocity", 3, velocity_},
            {"space", "displacement", 3, space_u_},
            {"space", "velocity", 3, space_v_}};
  }
  /// Quality row: fluid min and mean mean-ratio, min ratio to the initial, inverted count,
  /// space mesh min relative Jacobian.
  std::vector<double> quality() const {
    const auto q = mesh::cell_qualities(*s_.fluid_mesh, s_.flow->positions());
    double min_q = q.empty() ? 0.0 : q[0], mean = 0.0, ratio = 1e300, inverted = 0;
    for (std::size_t e = 0; e < q.size(); ++e) {
      min_q = std::min(min_q, q[e]);
      mean += q[e] / static_cast<double>(q.size());
      ratio = std::min(ratio, q[e] / q0_[e]);
      inverted += !(q[e] > 0.0);  // a NaN quality (NaN positions) is invalid too
    }
    const auto& sm = dynamic_cast<const motion::SpaceMeshMover&>(s_.flow->mover()).space_mesh();
    return {min_q, mean, ratio, inverted, sm.min_relative_jacobian()};
  }
  void add_outputs(RunControl& control) {
    if (fluid_pvd_) control.add_output(*fluid_pvd_);
    control.add_output(space_pvd_);
  }
  void write(long step, double t) {
    if (fluid_pvd_) {
      const std::string name = fmt::format("fluid_{:06}.vtu", step);
      io::write_mesh_vtu(outdir_ / name, *meshes_.fluid,
                         {{"displacement", 3, displacement_}, {"mesh_velocity", 3, velocity_}}, t, positions_);
      fluid_pvd_->add(t, name);
    }
    const auto& sm = dynamic_cast<const motion::SpaceMeshMover&>(s_.flow->mover()).space_mesh();
    const std::string name = fmt::format("space_{:06}.vtu", step);
    io::write_mesh_vtu(outdir_ / name, *meshes_.space, {{"displacement", 3, space_u_}, {"velocity", 3, space_v_}},
                       t, sm.current_positions());
    space_pvd_.add(t, name);
  }

 private:
  const setup::CoupledSystem& s_;
  const io::CaseMeshes& meshes_;
  std::filesystem::path outdir_;
  std::optional<io::PvdWriter> fluid_pvd_;
  io::PvdWriter space_pvd_;
  std::vector<double> q0_, displacement_, velocity_, space_u_, space_v_;
  std::vector<Vec3> positions_;
};

}  // namespace

void run_coupled(const RunContext& run) {
  const io::Case& c = run.c;
  const io::CaseMeshes& meshes = run.meshes;
  io::ProbeSet& probes = run.probes;
  const std::filesystem::path& outdir = run.outdir;
  const io::OutputMode mode = run.control.output_mode();
  const auto t_setup = Clock::now();
  // Before the setup: an unknown coupling.response.probe fails the run at once.
  const std::optional<std::size_t> response_index = io::response_probe(c);
  setup::CoupledSystem s = setup::build_coupled_system(c, meshes);
  const bool has_flow = c.fluid.has_value();
  spdlog::info("coupled run: shell {} nodes / {} load points, aerodynamics '{}'{}, {}",
               s.shell->num_nodes(), s.shell->load_points().size(), s.aerodynamics->name(),
               s.flow && s.flow->flow() ? fmt::format(" ({} fluid nodes)", s.fluid_mesh->num_nodes()) : "",
               !has_flow                      ? "no loads exchanged (the shell moves the fluid mesh)"
               : s.driver->options().monolithic ? "monolithic scheme"
               : s.driver->options().predictor == coupling::LoadPredictor::linear
                   ? "staggered scheme with the linear load predictor"
                   : "staggered scheme without load predictor");

  ShellWriter shell_writer(*s.shell, outdir, c.output.shell_stress, mode);
  std::optional<FluidWriter> fluid_writer;
  if (s.flow && s.flow->flow()) fluid_writer.emplace(*meshes.fluid, s.new_index, outdir, mode);
  std::optional<MeshWriter> mesh_writer;
  std::optional<io::ProbeWriter> quality_csv;
  if (s.flow) {
    mesh_writer.emplace(s, meshes, outdir, mode);
    quality_csv.emplace(outdir / "mesh_quality.csv",
                        std::vector<std::string>{"fluid_min_quality", "fluid_mean_quality", "fluid_min_quality_ratio",
                                                 "fluid_inverted", "space_min_relative_jacobian"},
                        mode);
  }
  io::ProbeWriter coupling_csv(outdir / "coupling.csv",
                               {"newton_iterations", "substeps", "shell_force_x", "shell_force_y", "shell_force_z",
                                "fluid_force_x", "fluid_force_y", "fluid_force_z", "force_balance"},
                               mode);
  double setup_seconds = seconds_since(t_setup);

  // The response probe's history, for OUTDIR/response.json at the end.
  std::vector<double> response_t, response_w;
  const auto write_response = [&] {
    if (!response_index) {
      spdlog::info("no response analysis: the case has no probe of shell.displacement; name the probe "
                   "to analyse in coupling.response.probe");
      return;
    }
    const io::ResponseSection& rs = c.coupling->response;
    const std::string& name = c.probes[*response_index].name;
    const coupling::ResponseAnalysis a = coupling::analyse_response(
        response_t, response_w, {.t_start = rs.t_start, .t_end = rs.t_end, .lco_cycles = rs.lco_cycles});
    std::ofstream(outdir / "response.json") << coupling::response_to_json(a, name) << '\n';
    if (a.extrema < 3) {
      spdlog::info("response of {} on [{:.6g}, {:.6g}] s: {} extrema, too few for a growth rate and a frequency "
                   "(3 needed)", name, a.t_start, a.t_end, a.extrema);
      return;
    }
    spdlog::info("response of {} on [{:.6g}, {:.6g}] s ({} extrema): growth rate {:.4g} ± {:.2g} 1/s, {:.5g} Hz; {}",
                 name, a.t_start, a.t_end, a.extrema, a.growth_rate, a.growth_rate_error, a.frequency_hz,
                 a.lco ? fmt::format("limit cycle amplitude {:.4g} ± {:.2g} at {:.5g} ± {:.2g} Hz (last {} cycles)",
                                     a.lco->amplitude, a.lco->amplitude_spread, a.lco->frequency_hz,
                                     a.lco->frequency_spread, a.lco->cycles)
                       : fmt::format("not saturated (envelope change {:.3g} over the last {} cycles)",
                                     a.envelope_change, rs.lco_cycles));
  };

  const shell::NewmarkSolver& solver = *s.solver;
  auto record = [&](long step, Record what) {
    const double t = solver.time();
    // Fresh views of every mesh this run moves; the initial ones of the others.
    const bool fresh_fluid = fluid_writer || mesh_writer, fresh_space = mesh_writer.has_value();
    std::vector<io::FieldView> fields;
    for (const auto& f : run.initial_fields)
      if (f.mesh != "shell" && !(f.mesh == "fluid" && fresh_fluid) && !(f.mesh == "space" && fresh_space))
        fields.push_back(f);
    for (const auto& v : shell_writer.update(solver.displacement(), &solver.velocity())) fields.push_back(v);
    if (fluid_writer)
      for (const auto& v : fluid_writer->update(*s.flow->flow())) fields.push_back(v);
    if (mesh_writer)
      for (const auto& v : mesh_writer->update())
        if (!(fluid_writer && v.mesh == "fluid")) fields.push_back(v);
    if (what != Record::fields) {
      probes.record(t, fields);
      if (response_index) {
        response_t.push_back(t);
        response_w.push_back(probes.sample(fields)[*response_index]);
      }
      if (quality_csv) quality_csv->append(t, mesh_writer->quality());
    }
    if (what == Record::probes) return;
    shell_writer.write(step, t, solver.displacement());
    if (fluid_writer) fluid_writer->write(step, *s.flow->flow());
    if (mesh_writer) mesh_writer->write(step, t);
  };

  const double dt = c.time->step;
  const auto steps = static_cast<long>(std::llround(c.time->end / dt));
  double steps_seconds = 0.0, output_seconds = 0.0, shell_seconds = 0.0, mesh_seconds = 0.0, flow_seconds = 0.0,
         transfer_seconds = 0.0;
  long newton_total = 0, substeps_total = 0;
  double worst_balance = 0.0;
  RunControl& control = run.control;
  control.add_output(probes.writer());
  control.add_output(coupling_csv);
  if (quality_csv) control.add_output(*quality_csv);
  control.add_output(shell_writer.pvd());
  if (fluid_writer) control.add_output(fluid_writer->pvd());
  if (mesh_writer) mesh_writer->add_outputs(control);
  control.set_state(
      "coupled",
      [&](ArchiveWriter& out) {
        s.driver->save(out);
        out.put(response_t);
        out.put(response_w);
        out.put(newton_total);
        out.put(substeps_total);
        out.put(worst_balance);
      },
      [&](ArchiveReader& in) {
        s.driver->restore(in);
        response_t = in.get_vector<double>();
        response_w = in.get_vector<double>();
        newton_total = in.get<long>();
        substeps_total = in.get<long>();
        worst_balance = in.get<double>();
      });
  if (control.restarting())
    control.restore();
  else
    record(0, Record::probes_and_fields);  // the solvers' initial state (its frames replace run_command's)
  // A run stopped by an error still writes response.json, of the steps done.
  struct ResponseOnError {
    const std::function<void()> write;
    ~ResponseOnError() {
      if (std::uncaught_exceptions() == 0) return;
      try {
        write();
      } catch (...) {  // the error on its way out is the one to report
      }
    }
  } response_on_error{write_response};
  const long last = run_time_loop(
      {steps, c.output.every, c.time->end, outdir, {}},
      [&](long step) {
        const auto t0 = Clock::now();
        const coupling::CouplingStepReport r = s.driver->step(dt);
        steps_seconds += seconds_since(t0);
        shell_seconds += r.shell_seconds;
        mesh_seconds += r.flow.mesh_seconds;
        flow_seconds += r.flow.flow_seconds;
        transfer_seconds += r.transfer_seconds;
        newton_total += r.newton_iterations;
        substeps_total += r.flow.substeps;
        const Vec3 ff = r.fluid_force.value_or(Vec3::Constant(std::nan("")));
        const double scale = std::max(r.shell_force.norm(), ff.allFinite() ? ff.norm() : 0.0);
        const double balance = ff.allFinite() && scale > 0.0 ? (r.shell_force - ff).norm() / scale : 0.0;
        worst_balance = std::max(worst_balance, balance);
        coupling_csv.append(r.time, std::vector<double>{double(r.newton_iterations), double(r.flow.substeps),
                                                        r.shell_force.x(), r.shell_force.y(), r.shell_force.z(),
                                                        ff.x(), ff.y(), ff.z(), balance});
        spdlog::debug("step {} t = {:.6g} s: {} Newton iterations, {} fluid sub-steps, shell force "
                      "({:.4g}, {:.4g}, {:.4g}) N, force balance {:.2e}",
                      step, r.time, r.newton_iterations, r.flow.substeps, r.shell_force.x(), r.shell_force.y(),
                      r.shell_force.z(), balance);
        return r.time;
      },
      [&](long step, Record what) {
        const auto t1 = Clock::now();
        record(step, what);
        output_seconds += seconds_since(t1);
      },
      [&] { return solver.time(); }, &control);
  spdlog::info("coupled run: {} shell steps to t = {:.6g} s, {} Newton iterations, {} fluid sub-steps; "
               "largest force imbalance {:.2e}",
               last, solver.time(), newton_total, substeps_total, worst_balance);
  spdlog::info("wall time {:.2f} s: setup {:.2f} s, shell {:.2f} s, fluid mesh motion {:.2f} s, flow {:.2f} s, "
               "load transfer {:.2f} s, output {:.2f} s",
               setup_seconds + steps_seconds + output_seconds, setup_seconds, shell_seconds, mesh_seconds,
               flow_seconds, transfer_seconds, output_seconds);
  write_response();
  if (run.plot && !c.probes.empty())
    make_plot("plot_flutter.py", {(outdir / "probes.csv").string(), "-o", outdir.string()});
  if (run.plot && quality_csv)
    make_plot("plot_probes.py", {(outdir / "mesh_quality.csv").string(), "-o", (outdir / "mesh_quality.png").string()});
}

}  // namespace shellflow::app
