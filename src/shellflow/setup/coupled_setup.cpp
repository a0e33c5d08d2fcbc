#include "shellflow/setup/coupled_setup.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>

#include "shellflow/core/error.h"
#include "shellflow/coupling/interface_maps.h"
#include "shellflow/fluid/ordering.h"
#include "shellflow/motion/mesh_mover.h"
#include "shellflow/setup/fluid_setup.h"
#include "shellflow/setup/motion_setup.h"
#include "shellflow/setup/shell_setup.h"

namespace shellflow::setup {
namespace {

coupling::CouplingIterationOptions iteration_options(const io::CouplingSection& k) {
  using A = io::CouplingSection::Acceleration::Type;
  coupling::CouplingIterationOptions o;
  o.max_iterations = k.iterations;
  o.tolerance = k.tolerance;
  const auto& a = k.acceleration;
  o.acceleration.type = a.type == A::constant  ? coupling::AccelerationType::constant
                        : a.type == A::aitken  ? coupling::AccelerationType::aitken
                        : a.type == A::iqn_ils ? coupling::AccelerationType::iqn_ils
                                               : coupling::AccelerationType::none;
  o.acceleration.relaxation = a.relaxation;
  o.acceleration.columns = a.columns;
  o.acceleration.reuse = a.reuse;
  o.acceleration.filter = a.filter;
  return o;
}

/// The wetted side must be one face of the whole shell: every load point the same sign.
double uniform_sign(std::span<const double> sign, const io::CouplingSection& k) {
  for (const double s : sign)
    if (s != sign.front())
      throw_at(k.where,
               "the shell's normals (its directors) point into the flow at some load points "
               "and away from it at others; the wetted face must be one face of the whole "
               "shell mesh (orient the shell's triangles consistently)");
  return sign.empty() ? 1.0 : sign.front();
}

}  // namespace

CoupledSystem build_coupled_system(const io::Case& c, const io::CaseMeshes& meshes, const CoupledRanks* ranks) {
  const io::CouplingSection& k = *c.coupling;
  const io::ShellAnalysis& analysis = *c.shell->analysis;
  CoupledSystem s;
  s.shell = std::make_unique<shell::ShellModel>(build_shell_model(*c.shell, *meshes.shell));
  shell::ShellModel& model = *s.shell;
  s.motion = std::make_unique<coupling::ShellStepMotion>(model, k.max_gap);
  const bool piston = c.fluid && c.fluid->model == io::FluidModelType::piston_theory;
  if (c.fluid) s.reference_pressure = c.fluid->free_stream.pressure;

  if (piston) {
    try {
      auto loads = std::make_unique<coupling::PistonLoads>(model, piston_flow(c, k.wet_normal));
      s.piston = loads.get();
      s.aerodynamics = std::move(loads);
    } catch (const InputError& e) {
      throw_at(k.where, e.what());
    }
  } else {
    // The flow runs on a copy renumbered for locality; the maps, the mover and the flow are
    // all built on it, after its wall nodes have been snapped onto the shell.
    s.fluid_mesh = std::make_unique<mesh::Mesh>(*meshes.fluid);
    mesh::Mesh& fluid_mesh = *s.fluid_mesh;
    s.new_index = fluid::renumber_for_locality(fluid_mesh);
    const shell::ShellLocator locator(model);
    coupling::WallNodeMap wall = coupling::map_wall_nodes(fluid_mesh, k.fluid_group, locator);
    try {
      coupling::check_gap(wall.gap, k.max_gap, "fluid wall nodes -> shell");
    } catch (const InputError& e) {
      throw_at(k.where, e.what());
    }
    coupling::snap_wall_nodes(fluid_mesh, wall, model);
    coupling::LoadPointMap loads = coupling::map_load_points(model, fluid_mesh, k.fluid_group);
    try {
      coupling::check_gap(loads.gap, k.max_gap, "shell load points -> fluid wall");
    } catch (const InputError& e) {
      throw_at(k.where, e.what());
    }
    spdlog::info(
        "coupling maps: {} fluid wall nodes -> shell (largest gap {:.2e} m, snapped), {} "
        "shell load points -> fluid wall (largest gap {:.2e} m)",
        wall.nodes.size(), wall.gap.max_gap, loads.sign.size(), loads.gap.max_gap);
    std::vector<double> areas = motion::lumped_node_areas(meshes.shell->nodes, meshes.shell->cells);
    auto mover = std::make_unique<motion::SpaceMeshMover>(fluid_mesh, *meshes.space, space_mesh_options(*c.motion),
                                                          *s.motion, meshes.shell->nodes, std::move(areas));
    const auto& r = mover->location_report();
    spdlog::info(
        "space mesh: located {} fluid nodes (max residual {:.2e} m), {} projected from "
        "outside (max gap {:.2e} m)",
        r.located, r.max_residual, r.projected, r.max_gap);
    std::unique_ptr<fluid::FluidModel> flow;
    coupling::FlowModelOptions options;
    options.substeps = k.substeps;
    options.interpolated_mesh_velocity = k.mesh_velocity == io::CouplingSection::MeshVelocity::interpolated;
    options.reference_pressure = s.reference_pressure;
    const bool distributed = c.fluid && ranks && ranks->ranks > 1;
    if (distributed) {
      RankShare share = rank_share(fluid_mesh, ranks->rank, ranks->ranks);
      s.part = std::move(share.part);
      flow = std::make_unique<fluid::FluidModel>(std::move(share.mesh), fluid_options(*c.fluid),
                                                 boundary_conditions(*c.fluid, nullptr), std::move(share.colouring));
    } else if (c.fluid) {
      flow = std::make_unique<fluid::FluidModel>(fluid_mesh, fluid_options(*c.fluid),
                                                 boundary_conditions(*c.fluid, nullptr));
    }
    if (c.fluid) {
      flow->set_state(initial_state(*c.fluid));
      options.cfl = c.fluid->analysis->cfl;
      const auto& kind = flow->boundaries().conditions();
      for (const auto& bc : kind)
        if (bc.group == k.fluid_group && bc.kind != fluid::BoundaryKind::slip_wall &&
            bc.kind != fluid::BoundaryKind::no_slip_wall)
          throw_at(k.where, fmt::format("coupling.fluid_group '{}' has the fluid boundary condition "
                                        "'{}'; the wet boundary must be a slip_wall (Euler) or a "
                                        "no_slip_wall",
                                        k.fluid_group, fluid::to_string(bc.kind)));
    }
    auto flow_model = std::make_unique<coupling::FlowModel>(fluid_mesh, std::move(flow), std::move(mover), *s.motion,
                                                            std::move(wall), std::move(loads), options);
    s.flow = flow_model.get();
    if (distributed) ranks->distribute(*s.part, *s.flow->flow(), *s.flow);
    s.aerodynamics = std::move(flow_model);
  }

  // The dry face: the cavity pressure relative to p_ref, a follower pressure along the
  // normal that points away from the cavity (into the flow), at the scheme's own time.
  if (c.fluid) {
    const double sign = uniform_sign(s.aerodynamics->sign(), k);
    const TimeFunction cavity = k.cavity_pressure ? *k.cavity_pressure : TimeFunction::constant(s.reference_pressure);
    shell::FollowerPressure p;
    p.pressure = sign;
    p.history = cavity.shifted(-s.reference_pressure);
    model.add_follower_pressure(p);
  }

  const TimeFunction load_function = analysis.load_function;
  s.solver = std::make_unique<shell::NewmarkSolver>(model, newmark_options(analysis),
                                                    [load_function](double t) { return load_function.value(t); });
  const bool monolithic = k.scheme == io::CouplingSection::Scheme::monolithic;
  if (monolithic) {
    s.piston_stiffness = std::make_unique<shell::SparseMatrix>();
    s.piston_damping = std::make_unique<shell::SparseMatrix>();
    s.piston->theory().matrices(*s.piston_stiffness, *s.piston_damping);
    s.solver->set_linear_load(s.piston_stiffness.get(), s.piston_damping.get());
  }
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.num_dofs());
  s.solver->set_initial_state(zero, zero);
  coupling::PartitionedOptions options;
  options.monolithic = monolithic;
  options.predictor = k.predictor == io::CouplingSection::Predictor::linear ? coupling::LoadPredictor::linear
                                                                            : coupling::LoadPredictor::none;
  options.iterations = iteration_options(k);
  // Pressure rises below 1e-10 of the free stream's are round-off to the blow-up monitor.
  if (c.fluid) options.iterations.noise_pressure = 1e-10 * c.fluid->free_stream.pressure;
  s.driver = std::make_unique<coupling::PartitionedSolver>(model, *s.solver, *s.aerodynamics, *s.motion, options);
  return s;
}

double added_mass_ratio(const io::Case& c) {
  if (!c.fluid || !c.shell || !c.time) return 0.0;
  const auto& f = c.fluid->free_stream;
  const double sound_speed = std::sqrt(c.fluid->gas.gamma * f.pressure / f.density);
  return f.density * sound_speed * c.time->step / (c.shell->material.density * c.shell->thickness);
}

static_assert(io::kPistonTheoryMinMach == coupling::kPistonTheoryMinMach, "one validity limit, two modules");

coupling::PistonTheoryFlow piston_flow(const io::Case& c, const Vec3& wet_normal) {
  // Speed and Mach number from the case's one conversion (U = M a).
  coupling::PistonTheoryFlow flow;
  flow.density = c.fluid->free_stream.density;
  flow.speed = free_stream_speed(*c.fluid);
  flow.mach = c.fluid->free_stream.mach;
  flow.direction = c.fluid->free_stream.direction;
  flow.wet_normal = wet_normal;
  return flow;
}

coupling::FlutterSetting flutter_setting(const io::Case& c, const shell::ShellModel& model) {
  coupling::FlutterSetting s;
  s.length = coupling::panel_length(model, c.fluid->free_stream.direction);
  const auto& m = c.shell->material;
  s.bending_stiffness =
      m.young_modulus * std::pow(c.shell->thickness, 3) / (12.0 * (1.0 - m.poisson_ratio * m.poisson_ratio));
  s.density = c.fluid->free_stream.density;
  s.pressure = c.fluid->free_stream.pressure;
  s.gamma = c.fluid->gas.gamma;
  s.mach = c.fluid->free_stream.mach;
  return s;
}

}  // namespace shellflow::setup
