#include "fluid_run.h"

#include "field_writers.h"
#include "time_loop.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

#include "fluid_fields.h"
#include "shellflow/core/error.h"
#include "shellflow/core/progress.h"
#include "shellflow/fluid/fluid_model.h"
#include "shellflow/fluid/ordering.h"
#include "shellflow/io/mesh_output.h"
#include "shellflow/io/pvd_writer.h"
#include "shellflow/setup/fluid_setup.h"

namespace shellflow::app {
namespace {

Vec3 displacement(const io::FluidMeshMotion& m, const Vec3& X, double t) {
  return {m.displacement[0](X, t), m.displacement[1](X, t), m.displacement[2](X, t)};
}

}  // namespace

void run_fluid(const RunContext& run) {
  const io::Case& c = run.c;
  const std::filesystem::path& outdir = run.outdir;
  const io::FluidSection& section = *c.fluid;
  const io::FluidAnalysis& analysis = *section.analysis;
  const mesh::Mesh& case_mesh = *run.meshes.fluid;

  // The solver works on a copy renumbered for memory locality; fields are mapped back.
  mesh::Mesh mesh = case_mesh;
  const std::vector<Index> new_index = fluid::renumber_for_locality(mesh);

  const fluid::FluidOptions options = setup::fluid_options(section);
  const fluid::Primitive free_stream = setup::free_stream(section);
  // Mesh velocity of the current step (prescribed motion): slip walls move with the mesh.
  const io::FluidMeshMotion* motion = section.mesh_motion ? &*section.mesh_motion : nullptr;
  std::vector<Vec3> mesh_velocity(motion ? mesh.nodes.size() : 0, Vec3::Zero());
  std::vector<fluid::BoundaryCondition> conditions =
      setup::boundary_conditions(section, motion ? &mesh_velocity : nullptr);
  fluid::FluidModel model(std::move(mesh), options, std::move(conditions));
  if (analysis.riemann) {
    const auto& r = *analysis.riemann;
    model.set_state([&](const Vec3& x) {
      return x.dot(r.normal) < r.position ? setup::primitive(r.left) : setup::primitive(r.right);
    });
  } else if (analysis.initial) {
    model.set_state([&](const Vec3& x) { return setup::primitive(*analysis.initial, x, 0.0); });
  } else {
    model.set_state([&](const Vec3&) { return free_stream; });
  }
  // Prescribed motion: x = X + d(X, t), w = (x^{n+1} - x^n) / dt.
  const std::vector<Vec3> initial_positions(model.positions().begin(), model.positions().end());
  std::vector<Vec3> next_positions(motion ? initial_positions.size() : 0);
  if (motion) {
    // Before the first step the time-step estimate uses the motion's velocity at t = 0.
    for (std::size_t a = 0; a < initial_positions.size(); ++a) {
      for (int d = 0; d < 3; ++d) {
        mesh_velocity[a][d] = motion->displacement[static_cast<std::size_t>(d)].time_derivative(
            initial_positions[a], 0.0);
      }
    }
    model.set_mesh_velocity(mesh_velocity);
  }

  FluidWriter writer(case_mesh, new_index, outdir, run.control.output_mode());
  auto record = [&](long step, Record what) {
    std::vector<io::FieldView> fields;
    for (const auto& v : run.initial_fields)
      if (v.mesh != "fluid") fields.push_back(v);
    const auto views = writer.update(model);
    fields.insert(fields.end(), views.begin(), views.end());
    if (what != Record::fields) run.probes.record(model.time(), fields);
    if (what != Record::probes) writer.write(step, model);
  };

  const bool steady = analysis.type == io::FluidAnalysisType::steady;
  const double end = steady ? static_cast<double>(analysis.steps) : c.time->end;
  double first_density_rate = 0.0;
  bool converged = false;
  run.control.add_output(run.probes.writer());
  run.control.add_output(writer.pvd());
  run.control.set_state(
      "flow",
      [&](ArchiveWriter& out) {
        model.save(out);
        out.put(first_density_rate);
        out.put(converged);
      },
      [&](ArchiveReader& in) {
        model.restore(in);
        first_density_rate = in.get<double>();
        converged = in.get<bool>();
      });
  if (run.control.restarting())
    run.control.restore();
  else
    record(0, Record::probes_and_fields);
  TimeLoop loop;
  loop.every = c.output.every;
  loop.end_time = end;
  loop.outdir = outdir;
  loop.more = [&](long completed) {
    return steady ? completed < analysis.steps && !converged : model.time() < c.time->end * (1 - 1e-12);
  };
  const long step = run_time_loop(
      loop,
      [&](long current) {
        if (steady) {
          model.step_local(analysis.cfl);
          if (current == 1) first_density_rate = model.density_rate();
          converged = analysis.residual_drop && model.density_rate() <= *analysis.residual_drop * first_density_rate;
          return static_cast<double>(current);
        }
        const double dt = std::min(model.stable_dt(analysis.cfl), c.time->end - model.time());
        if (motion) {
          const double t_next = model.time() + dt;
          const auto x = model.positions();
          for (std::size_t a = 0; a < initial_positions.size(); ++a) {
            next_positions[a] = initial_positions[a] + displacement(*motion, initial_positions[a], t_next);
            mesh_velocity[a] = (next_positions[a] - x[a]) / dt;
          }
          model.step(dt, next_positions, mesh_velocity);
        } else {
          model.step(dt);
        }
        return model.time();
      },
      record, [&] { return model.time(); }, &run.control);
  if (steady) {
    spdlog::info("steady flow: {} local steps, density rate {:.3e} ({:.2e} of the first step's)",
                 step, model.density_rate(),
                 model.density_rate() / std::max(first_density_rate, 1e-300));
    if (analysis.residual_drop && !converged) {
      spdlog::warn("steady flow: the density rate did not drop to {:g} of its first value in {} "
                   "steps; raise analysis.steps (or check the case)",
                   *analysis.residual_drop, analysis.steps);
    }
  } else {
    spdlog::info("flow: {} steps to t = {:.6g} s", step, model.time());
  }
}

}  // namespace shellflow::app
