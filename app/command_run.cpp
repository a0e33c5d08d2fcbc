// `shellflow run`: run a case.
//
// A run meshes the case, sets up its initial state (the shell at rest, the fluid at the free
// stream) and writes it (<mesh>_000000.vtu + <mesh>.pvd). Then, by the case's sections: a
// prescribed mesh motion (motion_run.h), a shell analysis (shell_run.h) or a flow analysis
// (fluid_run.h) — one of them — or, with a `coupling` section, the coupled run (coupled_run.h).
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <optional>

#include "commands.h"
#include "fluid_fields.h"
#include "motion_run.h"
#include "coupled_run.h"
#include "shell_run.h"
#include "fluid_run.h"
#include "output_dir.h"
#include "run_control.h"
#include "run_context.h"
#include "shellflow/io/case_meshes.h"
#include "shellflow/io/mesh_output.h"
#include "shellflow/io/probes.h"
#include "shellflow/io/pvd_writer.h"

namespace shellflow::app {
namespace {

/// Nodal fields of the initial state, by mesh.
struct InitialState {
  std::vector<double> shell_zero, shell_position;
  FluidFields fluid;
  std::vector<double> space_zero;
  std::vector<io::FieldView> views;
};

void fill(std::vector<double>& v, Index n, int components, double value) {
  v.assign(static_cast<std::size_t>(n) * static_cast<std::size_t>(components), value);
}

InitialState initial_state(const io::Case& c, const io::CaseMeshes& meshes) {
  InitialState s;
  if (const auto* m = meshes.find("shell")) {
    fill(s.shell_zero, m->num_nodes(), 3, 0.0);
    for (const Vec3& x : m->nodes) s.shell_position.insert(s.shell_position.end(), x.data(), x.data() + 3);
    for (auto q : {"displacement", "velocity", "acceleration"})
      s.views.push_back({"shell", q, 3, s.shell_zero});
    s.views.push_back({"shell", "position", 3, s.shell_position});
  }
  if (const auto* m = meshes.find("fluid"); m && c.fluid) {
    const auto& gas = c.fluid->gas;
    const auto& fs = c.fluid->free_stream;
    const double sound = std::sqrt(gas.gamma * fs.pressure / fs.density);
    const Vec3 u = fs.mach * sound * fs.direction;
    const Index n = m->num_nodes();
    fill(s.fluid.density, n, 1, fs.density);
    fill(s.fluid.pressure, n, 1, fs.pressure);
    fill(s.fluid.temperature, n, 1, fs.pressure / (fs.density * gas.gas_constant));
    fill(s.fluid.mach, n, 1, fs.mach);
    fill(s.fluid.energy, n, 1, fs.pressure / (gas.gamma - 1.0) + 0.5 * fs.density * u.squaredNorm());
    fill(s.fluid.mesh_velocity, n, 3, 0.0);
    for (Index i = 0; i < n; ++i) {
      s.fluid.velocity.insert(s.fluid.velocity.end(), u.data(), u.data() + 3);
      const Vec3 mom = fs.density * u;
      s.fluid.momentum.insert(s.fluid.momentum.end(), mom.data(), mom.data() + 3);
    }
    const auto views = s.fluid.views();
    s.views.insert(s.views.end(), views.begin(), views.end());
  }
  if (const auto* m = meshes.find("space")) {
    fill(s.space_zero, m->num_nodes(), 3, 0.0);
    s.views.push_back({"space", "displacement", 3, s.space_zero});
    s.views.push_back({"space", "velocity", 3, s.space_zero});
  }
  return s;
}

}  // namespace

int run_command(const CommonOptions& options, const StopOptions& stop) {
  const io::Case c = read_case(options);
  // A restart continues in the checkpoint's folder; every refusal comes before anything is
  // written there.
  std::optional<io::Checkpoint> checkpoint;
  std::filesystem::path outdir;
  if (stop.restart) {
    checkpoint = load_restart(*stop.restart, c);
    outdir = checkpoint->file.parent_path();
    if (outdir.empty()) outdir = ".";
    if (options.output_dir && std::filesystem::weakly_canonical(*options.output_dir) !=
                                  std::filesystem::weakly_canonical(outdir))
      throw Error(fmt::format("--restart {} continues the run in {}; drop -o {} (a restart writes into the folder "
                              "of its checkpoint)",
                              stop.restart->string(), outdir.string(), options.output_dir->string()));
  } else {
    outdir = prepare_output_dir(c, options);
  }
  spdlog::info("case '{}' -> {}", c.name, outdir.string());
  // A restart does not save the meshes again: the folder keeps the run's own.
  const io::CaseMeshes meshes =
      io::load_case_meshes(c, checkpoint ? std::nullopt : std::optional<std::filesystem::path>(outdir));
  std::vector<io::SectionDigest> digests = c.digests;
  for (const mesh::Mesh* m : meshes.all()) digests.push_back(io::mesh_digest(*m));
  RunControl control(c, outdir, stop, std::move(checkpoint), std::move(digests));
  // Only once the case is read and meshed (a case with an error keeps the old results), and
  // only here, not for `study` (its folder holds points/ and study.csv of a study to resume).
  if (!control.restarting()) remove_previous_run_output(outdir);
  const InitialState state = initial_state(c, meshes);
  io::ProbeSet probes(c.probes, meshes, outdir / "probes.csv", control.output_mode());

  const double time = 0.0;
  if (!control.restarting()) {
    for (const mesh::Mesh* m : meshes.all()) {
      std::vector<io::VtuField> fields;
      for (const auto& v : state.views)
        if (v.mesh == m->name) fields.push_back({std::string(v.quantity), v.components, v.values});
      const std::string vtu = fmt::format("{}_{:06}.vtu", m->name, 0);
      io::write_mesh_vtu(outdir / vtu, *m, std::move(fields), time);
      io::PvdWriter(outdir, m->name).add(time, vtu);
    }
  }
  const auto t_start = std::chrono::steady_clock::now();
  const RunContext run{c, meshes, probes, state.views, outdir, options.plot, control};
  if (c.coupling) {
    // Shell and flow (or piston theory, or only the fluid mesh) together.
    run_coupled(run);
  } else if (c.motion) {
    // Prescribed boundary motion, no flow: the mesh-motion tests of the paper.
    run_mesh_motion(run);
  } else if (c.shell && c.shell->analysis) {
    run_shell(run);
  } else if (c.fluid && c.fluid->analysis) {
    run_fluid(run);
  } else {
    control.not_time_stepping("a case without an analysis");
    probes.record(time, state.views);
    spdlog::warn("nothing to integrate: the case has no 'motion', 'shell.analysis' or "
                 "'fluid.analysis' (or a 'coupling' section); wrote "
                 "the initial state (t = 0) only");
  }
  control.log_summary(std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count());
  spdlog::info("wrote {}: <mesh>_NNNNNN.vtu, <mesh>.pvd, probes.csv", outdir.string());
  if (options.plot) make_plot("plot_probes.py", probe_plot_arguments(c, outdir));
  if (control.stopped()) {
    spdlog::warn("{}", control.stopped_message(options.case_file));
    return kStoppedExitCode;
  }
  return 0;
}

}  // namespace shellflow::app
