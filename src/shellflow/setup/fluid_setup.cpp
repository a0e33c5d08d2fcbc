#include "shellflow/setup/fluid_setup.h"

#include <cmath>
#include <optional>

#include "shellflow/core/error.h"
#include "shellflow/fluid/ordering.h"

namespace shellflow::setup {
namespace {

fluid::BoundaryKind kind_of(const io::FluidBoundary& b) {
  switch (b.type) {
    case io::FluidBoundaryType::supersonic_inflow:
      return fluid::BoundaryKind::supersonic_inflow;
    case io::FluidBoundaryType::supersonic_outflow:
      return fluid::BoundaryKind::supersonic_outflow;
    case io::FluidBoundaryType::far_field:
      return fluid::BoundaryKind::far_field;
    case io::FluidBoundaryType::slip_wall:
      return fluid::BoundaryKind::slip_wall;
    case io::FluidBoundaryType::symmetry:
      return fluid::BoundaryKind::symmetry;
    case io::FluidBoundaryType::no_slip_wall:
      return fluid::BoundaryKind::no_slip_wall;
  }
  throw_at(b.where, "unknown boundary type");
}

fluid::Viscosity viscosity_of(const io::Viscosity& v) {
  fluid::Viscosity mu;
  mu.law = v.law == io::ViscosityLaw::constant     ? fluid::ViscosityLaw::constant
           : v.law == io::ViscosityLaw::sutherland ? fluid::ViscosityLaw::sutherland
           : v.law == io::ViscosityLaw::power      ? fluid::ViscosityLaw::power
                                                   : fluid::ViscosityLaw::none;
  mu.mu_ref = v.mu_ref;
  mu.t_ref = v.t_ref;
  mu.sutherland = v.sutherland;
  mu.exponent = v.exponent;
  mu.prandtl = v.prandtl;
  return mu;
}

}  // namespace

fluid::Primitive primitive(const io::GasState& g) { return {g.density, g.velocity, g.pressure}; }

fluid::Primitive primitive(const io::SpaceTimeState& s, const Vec3& X, double t) {
  return {s.density(X, t), Vec3(s.velocity[0](X, t), s.velocity[1](X, t), s.velocity[2](X, t)), s.pressure(X, t)};
}

fluid::FluidOptions fluid_options(const io::FluidSection& section) {
  fluid::FluidOptions options;
  options.gas = fluid::IdealGas(section.gas.gamma, section.gas.gas_constant, viscosity_of(section.gas.viscosity));
  if (section.analysis) {
    options.q_dif = section.analysis->q_dif;
    options.consistent_mass_iterations = section.analysis->consistent_mass_iterations;
    options.weak_slip_walls = section.analysis->slip_walls == io::FluidSlipWalls::weak;
  }
  return options;
}

double free_stream_speed(const io::FluidSection& section) {
  const auto& fs = section.free_stream;
  return fs.mach * std::sqrt(section.gas.gamma * fs.pressure / fs.density);
}

fluid::Primitive free_stream(const io::FluidSection& section) {
  return {section.free_stream.density, free_stream_speed(section) * section.free_stream.direction,
          section.free_stream.pressure};
}

std::function<fluid::Primitive(const Vec3&)> initial_state(const io::FluidSection& section) {
  const io::FluidAnalysis* analysis = section.analysis ? &*section.analysis : nullptr;
  if (analysis && analysis->riemann) {
    const io::RiemannInitial r = *analysis->riemann;
    return [r](const Vec3& x) { return x.dot(r.normal) < r.position ? primitive(r.left) : primitive(r.right); };
  }
  if (analysis && analysis->initial) {
    const io::SpaceTimeState initial = *analysis->initial;
    return [initial](const Vec3& x) { return primitive(initial, x, 0.0); };
  }
  const fluid::Primitive inf = free_stream(section);
  return [inf](const Vec3&) { return inf; };
}

std::vector<fluid::BoundaryCondition> boundary_conditions(const io::FluidSection& section,
                                                          const std::vector<Vec3>* mesh_velocity) {
  const fluid::Primitive inf = free_stream(section);
  std::vector<fluid::BoundaryCondition> conditions;
  for (const io::FluidBoundary& b : section.boundaries) {
    fluid::BoundaryCondition& bc = conditions.emplace_back(b.group, kind_of(b), inf);
    if (b.state) {
      const io::SpaceTimeState* state = &*b.state;
      bc.state = primitive(*state, Vec3::Zero(), 0.0);
      bc.state_at = [state](const Vec3& x, double t) { return primitive(*state, x, t); };
    }
    if (b.type == io::FluidBoundaryType::no_slip_wall) {
      bc.wall_temperature = b.wall_temperature;
      if (mesh_velocity) {
        bc.wall_velocity = [mesh_velocity](Index node, const Vec3&, double) {
          return (*mesh_velocity)[static_cast<std::size_t>(node)];
        };
      } else if (b.wall_velocity) {
        bc.wall_velocity = [v = &*b.wall_velocity](Index, const Vec3& x, double t) {
          return Vec3((*v)[0](x, t), (*v)[1](x, t), (*v)[2](x, t));
        };
      }
    }
    if (mesh_velocity && b.type == io::FluidBoundaryType::slip_wall) {
      bc.wall_velocity = [mesh_velocity](Index node, const Vec3&, double) {
        return (*mesh_velocity)[static_cast<std::size_t>(node)];
      };
    }
  }
  return conditions;
}

RankShare rank_share(const mesh::Mesh& whole, int rank, int ranks) {
  RankShare share;
  share.part = std::make_unique<FlowPart>();
  FlowPart& part = *share.part;
  part.ranks = ranks;
  part.whole_nodes = whole.num_nodes();
  part.node_owner = mesh::node_owners(whole, mesh::partition_cells(whole, ranks));
  part.local = mesh::make_local_part(whole, part.node_owner, rank);
  share.colouring = fluid::restrict_colouring(
      fluid::colour_cells(whole.cells.connectivity, 4, whole.num_nodes(), fluid::default_block_size(whole.num_cells())),
      part.local.cells);
  share.mesh = mesh::local_mesh(whole, part.local);
  return share;
}

Flow build_flow(const io::FluidSection& section, const mesh::Mesh& case_mesh, int rank, int ranks) {
  Flow flow;
  mesh::Mesh mesh = case_mesh;
  flow.new_index = fluid::renumber_for_locality(mesh);
  std::optional<fluid::CellColouring> colouring;
  if (ranks > 1) {
    RankShare share = rank_share(mesh, rank, ranks);
    flow.part = std::move(share.part);
    mesh = std::move(share.mesh);
    colouring = std::move(share.colouring);
  }
  const io::FluidMeshMotion* motion = section.mesh_motion ? &*section.mesh_motion : nullptr;
  if (motion) flow.mesh_velocity = std::make_unique<std::vector<Vec3>>(mesh.nodes.size(), Vec3::Zero());
  flow.model =
      std::make_unique<fluid::FluidModel>(std::move(mesh), fluid_options(section),
                                          boundary_conditions(section, flow.mesh_velocity.get()), std::move(colouring));
  fluid::FluidModel& model = *flow.model;
  model.set_state(initial_state(section));
  if (motion) {
    // Before the first step the time-step estimate uses the motion's velocity at t = 0.
    std::vector<Vec3>& w = *flow.mesh_velocity;
    const auto x = model.positions();
    for (std::size_t a = 0; a < w.size(); ++a)
      for (int d = 0; d < 3; ++d)
        w[a][d] = motion->displacement[static_cast<std::size_t>(d)].time_derivative(x[a], 0.0);
    model.set_mesh_velocity(w);
  }
  return flow;
}

}  // namespace shellflow::setup
