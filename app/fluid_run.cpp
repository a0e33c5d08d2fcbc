#include "fluid_run.h"

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

namespace shellflow::app {
namespace {

fluid::BoundaryKind kind_of(const io::FluidBoundary& b) {
  switch (b.type) {
    case io::FluidBoundaryType::supersonic_inflow: return fluid::BoundaryKind::supersonic_inflow;
    case io::FluidBoundaryType::supersonic_outflow: return fluid::BoundaryKind::supersonic_outflow;
    case io::FluidBoundaryType::far_field: return fluid::BoundaryKind::far_field;
    case io::FluidBoundaryType::slip_wall: return fluid::BoundaryKind::slip_wall;
    case io::FluidBoundaryType::symmetry: return fluid::BoundaryKind::symmetry;
    case io::FluidBoundaryType::no_slip_wall: return fluid::BoundaryKind::no_slip_wall;
  }
  throw_at(b.where, "unknown boundary type");
}

fluid::Viscosity viscosity_of(const io::Viscosity& v) {
  fluid::Viscosity mu;
  mu.law = v.law == io::ViscosityLaw::constant     ? fluid::ViscosityLaw::constant
           : v.law == io::ViscosityLaw::sutherland ? fluid::ViscosityLaw::sutherland
                                                   : fluid::ViscosityLaw::none;
  mu.mu_ref = v.mu_ref;
  mu.t_ref = v.t_ref;
  mu.sutherland = v.sutherland;
  mu.prandtl = v.prandtl;
  return mu;
}

fluid::Primitive primitive(const io::GasState& g) { return {g.density, g.velocity, g.pressure}; }

fluid::Primitive primitive(const io::SpaceTimeState& s, const Vec3& X, double t) {
  return {s.density(X, t), Vec3(s.velocity[0](X, t), s.velocity[1](X, t), s.velocity[2](X, t)),
          s.pressure(X, t)};
}

Vec3 displacement(const io::FluidMeshMotion& m, const Vec3& X, double t) {
  return {m.displacement[0](X, t), m.displacement[1](X, t), m.displacement[2](X, t)};
}

/// Nodal fields of the flow, in the case mesh's node order.
FluidFields flow_fields(const fluid::FluidModel& model, const std::vector<Index>& new_index) {
  const auto& gas = model.options().gas;
  const std::size_t n = new_index.size();
  FluidFields f;
  f.density.resize(n);
  f.pressure.resize(n);
  f.temperature.resize(n);
  f.mach.resize(n);
  f.energy.resize(n);
  f.velocity.resize(3 * n);
  f.momentum.resize(3 * n);
  f.mesh_velocity.resize(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const Index k = new_index[i];
    const fluid::Primitive p = model.primitive(k);
    const auto q = model.state().get(k);
    f.density[i] = p.rho;
    f.pressure[i] = p.pressure;
    f.temperature[i] = gas.temperature(p.rho, p.pressure);
    f.mach[i] = p.velocity.norm() / gas.sound_speed(p.rho, p.pressure);
    f.energy[i] = q.energy;
    for (int d = 0; d < 3; ++d) {
      f.velocity[3 * i + static_cast<std::size_t>(d)] = p.velocity[d];
      f.momentum[3 * i + static_cast<std::size_t>(d)] = q.momentum[d];
      f.mesh_velocity[3 * i + static_cast<std::size_t>(d)] =
          model.mesh_velocity()[static_cast<std::size_t>(k)][d];
    }
  }
  return f;
}

}  // namespace

void run_fluid(const io::Case& c, const io::CaseMeshes& meshes, io::ProbeSet& probes,
               std::span<const io::FieldView> initial_fields, const std::filesystem::path& outdir) {
  const io::FluidSection& section = *c.fluid;
  const io::FluidAnalysis& analysis = *section.analysis;
  const mesh::Mesh& case_mesh = *meshes.fluid;

  // The solver works on a copy renumbered for memory locality; fields are mapped back.
  mesh::Mesh mesh = case_mesh;
  const std::vector<Index> new_index = fluid::renumber_for_locality(mesh);

  fluid::FluidOptions options;
  options.gas = fluid::IdealGas(section.gas.gamma, section.gas.gas_constant,
                                viscosity_of(section.gas.viscosity));
  options.q_dif = analysis.q_dif;
  options.consistent_mass_iterations = analysis.consistent_mass_iterations;
  const double sound = std::sqrt(section.gas.gamma * section.free_stream.pressure /
                                 section.free_stream.density);
  const fluid::Primitive free_stream{section.free_stream.density,
                                     section.free_stream.mach * sound * section.free_stream.direction,
                                     section.free_stream.pressure};
  // Mesh velocity of the current step (prescribed motion): slip walls move with the mesh.
  const io::FluidMeshMotion* motion = section.mesh_motion ? &*section.mesh_motion : nullptr;
  std::vector<Vec3> mesh_velocity(motion ? mesh.nodes.size() : 0, Vec3::Zero());
  std::vector<fluid::BoundaryCondition> conditions;
  for (const io::FluidBoundary& b : section.boundaries) {
    fluid::BoundaryCondition& bc = conditions.emplace_back(b.group, kind_of(b), free_stream);
    if (b.state) {
      const io::SpaceTimeState* state = &*b.state;
      bc.state = primitive(*state, Vec3::Zero(), 0.0);
      bc.state_at = [state](const Vec3& x, double t) { return primitive(*state, x, t); };
    }
    if (b.type == io::FluidBoundaryType::no_slip_wall) {
      bc.wall_temperature = b.wall_temperature;
      if (motion) {
        bc.wall_velocity = [&mesh_velocity](Index node, const Vec3&, double) {
          return mesh_velocity[static_cast<std::size_t>(node)];
        };
      } else if (b.wall_velocity != Vec3::Zero()) {
        bc.wall_velocity = [v = b.wall_velocity](Index, const Vec3&, double) { return v; };
      }
    }
    if (motion && b.type == io::FluidBoundaryType::slip_wall) {
      bc.wall_velocity = [&mesh_velocity](Index node, const Vec3&, double) {
        return mesh_velocity[static_cast<std::size_t>(node)];
      };
    }
  }
  fluid::FluidModel model(std::move(mesh), options, std::move(conditions));
  if (analysis.riemann) {
    const auto& r = *analysis.riemann;
    model.set_state([&](const Vec3& x) {
      return x.dot(r.normal) < r.position ? primitive(r.left) : primitive(r.right);
    });
  } else if (analysis.initial) {
    model.set_state([&](const Vec3& x) { return primitive(*analysis.initial, x, 0.0); });
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

  io::PvdWriter pvd(outdir, "fluid");
  std::vector<Vec3> positions(case_mesh.nodes.size());
  auto record = [&](long step, bool write_fields) {
    const FluidFields f = flow_fields(model, new_index);
    std::vector<io::FieldView> fields;
    for (const auto& v : initial_fields)
      if (v.mesh != "fluid") fields.push_back(v);
    const auto views = f.views();
    fields.insert(fields.end(), views.begin(), views.end());
    probes.record(model.time(), fields);
    if (!write_fields) return;
    for (std::size_t i = 0; i < positions.size(); ++i)
      positions[i] = model.positions()[static_cast<std::size_t>(new_index[i])];
    const std::vector<double> model_nu = model.nodal_artificial_viscosity();
    std::vector<double> nu(new_index.size());
    for (std::size_t i = 0; i < nu.size(); ++i) nu[i] = model_nu[static_cast<std::size_t>(new_index[i])];
    const std::string name = fmt::format("fluid_{:06}.vtu", step);
    io::write_mesh_vtu(outdir / name, case_mesh,
                       {{"density", 1, f.density},
                        {"velocity", 3, f.velocity},
                        {"pressure", 1, f.pressure},
                        {"mach", 1, f.mach},
                        {"temperature", 1, f.temperature},
                        {"mesh_velocity", 3, f.mesh_velocity},
                        {"artificial_viscosity", 1, nu}},
                       model.time(), positions);
    pvd.add(model.time(), name);
  };

  record(0, true);
  const bool steady = analysis.type == io::FluidAnalysisType::steady;
  const double end = steady ? static_cast<double>(analysis.steps) : c.time->end;
  Progress progress(0.0, end);
  long step = 0;
  double first_density_rate = 0.0;
  bool converged = false;
  try {
    while (steady ? step < analysis.steps && !converged : model.time() < c.time->end * (1 - 1e-12)) {
      if (steady) {
        model.step_local(analysis.cfl);
        if (step == 0) first_density_rate = model.density_rate();
        converged = analysis.residual_drop &&
                    model.density_rate() <= *analysis.residual_drop * first_density_rate;
      } else if (motion) {
        const double dt = std::min(model.stable_dt(analysis.cfl), c.time->end - model.time());
        const double t_next = model.time() + dt;
        const auto x = model.positions();
        for (std::size_t a = 0; a < initial_positions.size(); ++a) {
          next_positions[a] = initial_positions[a] + displacement(*motion, initial_positions[a], t_next);
          mesh_velocity[a] = (next_positions[a] - x[a]) / dt;
        }
        model.step(dt, next_positions, mesh_velocity);
      } else {
        model.step(std::min(model.stable_dt(analysis.cfl), c.time->end - model.time()));
      }
      ++step;
      const bool last =
          steady ? step == analysis.steps || converged : model.time() >= c.time->end * (1 - 1e-12);
      record(step, step % c.output.every == 0 || last);
      progress.update(steady ? static_cast<double>(step) : model.time(), step);
    }
  } catch (const SolverError& e) {
    // The model keeps the last valid state: write it before reporting.
    record(step, true);
    throw SolverError(fmt::format("{}; the last valid state (t = {:.6g} s) is in {}", e.what(),
                                  model.time(), outdir.string()));
  }
  progress.finish();
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
