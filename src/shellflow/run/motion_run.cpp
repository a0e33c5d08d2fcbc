#include "motion_run.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "commands.h"
#include "field_writers.h"
#include "time_loop.h"
#include "shellflow/core/error.h"
#include "shellflow/core/progress.h"
#include "shellflow/io/mesh_output.h"
#include "shellflow/io/probe_writer.h"
#include "shellflow/io/pvd_writer.h"
#include "shellflow/mesh/quality.h"
#include "shellflow/motion/laplace_mover.h"
#include "shellflow/motion/mesh_mover.h"
#include "shellflow/setup/motion_setup.h"

namespace shellflow::app {
namespace {

std::unique_ptr<motion::PanelModesMotion> prescribed_motion(const io::MotionSection& m) {
  if (!m.prescribed) {
    throw_at(m.where, "a mesh-motion run needs 'prescribed' (the boundary motion) until a shell "
                      "solver drives it");
  }
  const auto& p = *m.prescribed;
  std::vector<motion::PanelModesMotion::Mode> modes;
  for (const auto& mode : p.modes) modes.push_back({mode.wave_number, mode.amplitude});
  return std::make_unique<motion::PanelModesMotion>(p.leading_edge, p.direction, p.length,
                                                    p.normal, std::move(modes));
}

std::unique_ptr<motion::FluidMeshMover> make_mover(const io::MotionSection& m,
                                                   const io::CaseMeshes& meshes,
                                                   motion::BoundaryMotion& boundary) {
  const auto weighting = m.weighting == io::MotionWeighting::area ? motion::IdwWeighting::area
                                                                  : motion::IdwWeighting::plain;
  const mesh::Mesh& fluid = *meshes.fluid;
  switch (m.method) {
    case io::MotionMethod::space_mesh: {
      const motion::SpaceMeshOptions options = setup::space_mesh_options(m);
      // IDW samples: the shell's nodes when the case has a shell mesh (the paper's sums),
      // else the fluid mesh's interface nodes.
      std::vector<Vec3> samples;
      std::vector<double> areas;
      if (meshes.shell) {
        samples = meshes.shell->nodes;
        areas = motion::lumped_node_areas(meshes.shell->nodes, meshes.shell->cells);
      }
      auto mover = std::make_unique<motion::SpaceMeshMover>(fluid, *meshes.space, options, boundary,
                                                            samples, areas);
      const auto& r = mover->location_report();
      spdlog::info("space mesh: located {} fluid nodes (max residual {:.2e} m, {} Newton "
                   "iterations at most), {} projected from outside (max gap {:.2e} m)",
                   r.located, r.max_residual, r.max_newton_iterations, r.projected, r.max_gap);
      return mover;
    }
    case io::MotionMethod::direct_idw:
      return std::make_unique<motion::DirectIdwMover>(
          fluid, motion::BoundaryGroups{m.interface_groups, m.fixed_groups, m.sliding_groups},
          boundary, m.interface_exponent, m.fixed_exponent, weighting);
    case io::MotionMethod::laplace:
      return std::make_unique<motion::LaplaceMover>(
          fluid, motion::BoundaryGroups{m.interface_groups, m.fixed_groups, m.sliding_groups},
          boundary);
  }
  throw Error("unknown motion method");
}


}  // namespace

void run_mesh_motion(const RunContext& run) {
  const io::Case& c = run.c;
  const std::filesystem::path& outdir = run.outdir;
  const io::MotionSection& m = *c.motion;
  auto boundary = prescribed_motion(m);
  auto mover = make_mover(m, run.meshes, *boundary);
  const auto* space_mover = dynamic_cast<const motion::SpaceMeshMover*>(mover.get());
  const mesh::Mesh& fluid = *run.meshes.fluid;
  const io::OutputMode mode = run.control.output_mode();

  std::vector<std::string> columns;
  for (std::size_t k = 0; k < m.prescribed->modes.size(); ++k) columns.push_back(fmt::format("A{}", k + 1));
  for (auto name : {"fluid_min_quality", "fluid_mean_quality", "fluid_min_quality_ratio",
                    "fluid_inverted"})
    columns.emplace_back(name);
  if (space_mover) {
    columns.emplace_back("space_min_quality");
    columns.emplace_back("space_min_relative_jacobian");
  }
  io::ProbeWriter quality_csv(outdir / "motion_quality.csv", columns, mode);
  io::PvdWriter fluid_pvd(outdir, "fluid", mode);
  std::optional<io::PvdWriter> space_pvd;
  if (space_mover) space_pvd.emplace(outdir, "space", mode);

  const std::vector<double> q0 = mesh::cell_qualities(fluid);
  std::vector<Vec3> x(fluid.nodes.size()), w(x.size()), displacement(x.size());
  const double dt = c.time->step;
  const auto steps = static_cast<long>(std::llround(c.time->end / dt));
  std::vector<double> u_flat, w_flat, su, sv;
  // The fields of the state of step `step` (x, w and the space mesh's) for probes and VTU.
  auto update_fields = [&] {
    for (std::size_t i = 0; i < x.size(); ++i) displacement[i] = x[i] - fluid.nodes[i];
    u_flat = flatten(displacement);
    w_flat = flatten(w);
    if (space_mover) {
      su = flatten(space_mover->space_mesh().displacement());
      sv = flatten(space_mover->space_mesh().velocity());
    }
  };
  // Moves the mesh to step `step`: quality row, or (an inverted element) the state of the
  // step before restored and a SolverError.
  auto advance = [&](long step) {
    const double t = static_cast<double>(step) * dt;
    mover->update(t, x, w);
    const auto q = mesh::cell_qualities(fluid, x);
    Index inverted = 0, worst = 0;
    double min_q = q.empty() ? 0.0 : q[0], mean_q = 0.0, min_ratio = 1e300;
    for (std::size_t e = 0; e < q.size(); ++e) {
      inverted += !(q[e] > 0.0);  // a NaN quality (NaN positions) is invalid too
      mean_q += q[e] / static_cast<double>(q.size());
      min_ratio = std::min(min_ratio, q[e] / q0[e]);
      if (q[e] < min_q || (std::isnan(q[e]) && !std::isnan(min_q))) {
        min_q = q[e];
        worst = static_cast<Index>(e);
      }
    }
    if (inverted > 0) {
      const auto v = fluid.cells.element(worst);
      const Vec3 centre = 0.25 * (x[v[0]] + x[v[1]] + x[v[2]] + x[v[3]]);
      // The last valid state (the movers are deterministic: recompute it) for the loop to write.
      if (step > 0) mover->update(static_cast<double>(step - 1) * dt, x, w);
      update_fields();
      throw SolverError(fmt::format(
          "t = {:.6g} s: the mesh motion inverts {} fluid element(s), the worst {} at ({:.4g}, {:.4g}, {:.4g}) m; "
          "reduce the amplitude or change motion.method / the IDW exponents",
          t, inverted, worst, centre.x(), centre.y(), centre.z()));
    }
    std::vector<double> row;
    for (const auto& mode : m.prescribed->modes) row.push_back(mode.amplitude.value(t));
    // The space mesh's own health: vertex quality, and the Jacobian of its cubic map, which
    // turns negative before the fluid mesh inverts (the early warning).
    row.insert(row.end(), {min_q, mean_q, min_ratio, static_cast<double>(inverted)});
    if (space_mover) {
      const auto& sm = space_mover->space_mesh();
      row.push_back(mesh::summarize_quality(sm.mesh(), sm.current_positions()).min);
      row.push_back(sm.min_relative_jacobian());
    }
    quality_csv.append(t, row);
    update_fields();
    return t;
  };
  double t_state = 0.0;  // time of the state in x, w
  auto record = [&](long step, Record what) {
    const double t = static_cast<double>(step) * dt;
    t_state = t;
    if (what != Record::fields) {
      std::vector<io::FieldView> fields(run.initial_fields.begin(), run.initial_fields.end());
      std::erase_if(fields, [](const io::FieldView& f) { return f.mesh == "fluid" && f.quantity == "mesh_velocity"; });
      fields.push_back({"fluid", "mesh_velocity", 3, w_flat});
      if (space_mover) {
        std::erase_if(fields, [](const io::FieldView& f) { return f.mesh == "space"; });
        fields.push_back({"space", "displacement", 3, su});
        fields.push_back({"space", "velocity", 3, sv});
      }
      run.probes.record(t, fields);
    }
    if (what == Record::probes) return;
    const std::string name = fmt::format("fluid_{:06}.vtu", step);
    io::write_mesh_vtu(outdir / name, fluid, {{"displacement", 3, u_flat}, {"mesh_velocity", 3, w_flat}}, t, x);
    fluid_pvd.add(t, name);
    if (space_mover) {
      const auto xs = space_mover->space_mesh().current_positions();
      const std::string sname = fmt::format("space_{:06}.vtu", step);
      io::write_mesh_vtu(outdir / sname, *run.meshes.space, {{"displacement", 3, su}, {"velocity", 3, sv}}, t, xs);
      space_pvd->add(t, sname);
    }
  };

  run.control.add_output(run.probes.writer());
  run.control.add_output(quality_csv);
  run.control.add_output(fluid_pvd);
  if (space_pvd) run.control.add_output(*space_pvd);
  // The movers are algebraic in time (the Laplace mover's warm start aside): the state is
  // the mover's.
  run.control.set_state(
      "mesh motion", [&](ArchiveWriter& out) { mover->save(out); }, [&](ArchiveReader& in) { mover->restore(in); });
  if (run.control.restarting()) {
    run.control.restore();
  } else {
    try {
      advance(0);
    } catch (const SolverError& e) {
      throw SolverError(fmt::format("{} (step 0); nothing but the initial mesh is in {}", e.what(), outdir.string()));
    }
    record(0, Record::probes_and_fields);
  }
  const long last = run_time_loop({steps, c.output.every, c.time->end, outdir, {}}, advance, record,
                                  [&] { return t_state; }, &run.control);
  std::fflush(stdout);
  if (run.plot)
    make_plot("plot_probes.py", {(outdir / "motion_quality.csv").string(), "--x", "A1", "-o",
                                 (outdir / "motion_quality.png").string()});
  if (!run.control.stopped())
    spdlog::info("mesh motion: {} steps, fluid mesh valid throughout; quality history in {}", last,
                 (outdir / "motion_quality.csv").string());
}

}  // namespace shellflow::app
