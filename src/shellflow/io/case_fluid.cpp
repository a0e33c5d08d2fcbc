// The `fluid` section of a case file: gas, free stream, boundaries, mesh motion and the
// analysis; the space-time expressions (SpaceTimeScalar) of its states.
#include <fmt/format.h>

#include <array>
#include <cmath>
#include <map>
#include <string_view>
#include <utility>

#include "shellflow/core/error.h"
#include "shellflow/io/case_sections.h"

namespace shellflow::io {

namespace {

/// Variables of the space-time expressions of a case file, in the order SpaceTimeScalar
/// passes them: initial coordinates, then time.
constexpr std::array<std::string_view, 4> kSpaceTimeVariables = {"x", "y", "z", "t"};

/// A number or an expression of x, y, z, t (docs/case-format.md "Expressions"); `fail`
/// reports a message at the value's line.
template <class Fail>
SpaceTimeScalar parse_space_time_scalar(std::string_view text, const SourceLocation& where, Fail&& fail) {
  try {
    return SpaceTimeScalar(Expression::parse(text, kSpaceTimeVariables), where.prefix());
  } catch (const InputError& e) {
    fail(std::string(e.what()));
  }
  return {};
}

SpaceTimeScalar read_space_time_scalar(const YamlNode& parent, std::string_view key) {
  return parse_space_time_scalar(parent.required<std::string>(key), parent.location(key),
                                 [&](const std::string& what) { parent.fail(key, what); });
}

/// A list of three numbers or expressions.
std::array<SpaceTimeScalar, 3> read_space_time_vector(const YamlNode& parent, std::string_view key) {
  const std::vector<YamlNode> items = parent.list(key);
  if (items.size() != 3) parent.fail(key, fmt::format("expected 3 components, got {}", items.size()));
  std::array<SpaceTimeScalar, 3> v;
  for (std::size_t d = 0; d < 3; ++d) {
    if (!items[d].is_scalar()) items[d].fail("expected a number or an expression in quotes");
    v[d] = parse_space_time_scalar(items[d].as<std::string>(), items[d].location(),
                                   [&](const std::string& what) { items[d].fail(what); });
  }
  return v;
}

/// {density, velocity: [3], pressure}, each a number or an expression of x, y, z, t.
SpaceTimeState read_space_time_state(const YamlNode& node) {
  node.expect_map();
  SpaceTimeState s;
  s.where = node.location();
  s.density = read_space_time_scalar(node, "density");
  s.pressure = read_space_time_scalar(node, "pressure");
  if (node.has("velocity")) s.velocity = read_space_time_vector(node, "velocity");
  node.finish();
  return s;
}

}  // namespace

namespace detail {

FluidSection read_fluid(const YamlNode& node, std::vector<GroupReference>& refs) {
  FluidSection fluid;
  fluid.model = read_enum(node, "model", kFluidModels, FluidModelType::euler);
  if (fluid.model == FluidModelType::piston_theory) {
    for (const std::string_view key : {"boundaries", "mesh_motion", "analysis"})
      if (node.has(key))
        node.fail(key,
                  "piston theory computes the loads from the shell's motion, without a fluid "
                  "mesh; remove it (or use model: euler)");
  }
  if (auto gas = node.optional_child("gas")) {
    fluid.gas.gamma = gas->optional<double>("gamma", 1.4, Range::greater_than(1));
    fluid.gas.gas_constant = gas->optional<double>("gas_constant", 287.05, Range::positive(), "J/(kg K)");
    if (fluid.model == FluidModelType::piston_theory && gas->has("viscosity"))
      gas->fail("viscosity",
                "piston theory is inviscid and takes no shear; remove it (or use model: euler with a "
                "no_slip_wall for a viscous flow)");
    if (auto v = gas->optional_child("viscosity")) {
      Viscosity& mu = fluid.gas.viscosity;
      mu.law = read_enum(*v, "law", kViscosityLaws);
      mu.mu_ref = v->optional<double>("mu_ref", mu.mu_ref, Range::positive(), "Pa s");
      mu.prandtl = v->optional<double>("prandtl", mu.prandtl, Range::positive());
      if (mu.law == ViscosityLaw::power) {
        mu.t_ref = v->optional<double>("t_ref", mu.t_ref, Range::positive(), "K");
        mu.exponent = v->optional<double>("exponent", mu.exponent, Range::in_range(0.0, 2.0));
      }
      if (mu.law == ViscosityLaw::sutherland) {
        mu.t_ref = v->optional<double>("t_ref", mu.t_ref, Range::positive(), "K");
        mu.sutherland = v->optional<double>("sutherland", mu.sutherland, Range::non_negative(), "K");
      }
      v->finish();
    }
    gas->finish();
  }

  const YamlNode stream = node.child("free_stream");
  fluid.free_stream.density = stream.required<double>("density", Range::positive(), "kg/m^3");
  fluid.free_stream.pressure = stream.required<double>("pressure", Range::positive(), "Pa");
  fluid.free_stream.mach = stream.required<double>("mach", Range::non_negative());
  fluid.free_stream.direction = unit_vector(stream, "direction", stream.vec3("direction", Vec3::UnitX()));
  stream.finish();

  std::map<std::string, int> first_line;  // group -> line of its first boundary condition
  for (const YamlNode& item : node.optional_list("boundaries")) {
    item.expect_map();
    FluidBoundary b;
    b.where = item.location();
    b.group = read_group(item, "fluid", refs);
    b.type = read_enum(item, "type", kFluidBoundaryTypes);
    if (auto s = item.optional_child("state")) {
      if (b.type != FluidBoundaryType::supersonic_inflow && b.type != FluidBoundaryType::far_field) {
        item.fail("state", fmt::format("a '{}' boundary takes no state; only supersonic_inflow "
                                       "and far_field do",
                                       to_string(b.type)));
      }
      b.state = read_space_time_state(*s);
    }
    for (const std::string_view key : {"velocity", "temperature"}) {
      if (b.type != FluidBoundaryType::no_slip_wall && item.has(key)) {
        item.fail(key, fmt::format("only no_slip_wall boundaries take a wall {}", key));
      }
    }
    if (b.type == FluidBoundaryType::no_slip_wall) {
      if (item.has("velocity")) b.wall_velocity = read_space_time_vector(item, "velocity");
      b.wall_temperature = item.maybe<double>("temperature");
      if (b.wall_temperature && !(*b.wall_temperature > 0.0)) {
        item.fail("temperature", fmt::format("must be > 0 K, got {}", *b.wall_temperature));
      }
    }
    const auto [it, inserted] = first_line.emplace(b.group, item.location("group").line);
    if (!inserted) {
      item.fail("group", fmt::format("group '{}' already has a boundary condition (line {}); "
                                     "expected one condition per group",
                                     b.group, it->second));
    }
    item.finish();
    fluid.boundaries.push_back(std::move(b));
  }
  if (auto m = node.optional_child("mesh_motion")) {
    FluidMeshMotion motion;
    motion.where = m->location();
    motion.displacement = read_space_time_vector(*m, "displacement");
    m->finish();
    fluid.mesh_motion = std::move(motion);
  }
  if (auto a = node.optional_child("analysis")) {
    FluidAnalysis analysis;
    analysis.where = a->location();
    analysis.type = read_enum(*a, "type", kFluidAnalysisTypes);
    analysis.q_dif = a->optional<double>("q_dif", 0.0, Range::non_negative());
    analysis.consistent_mass_iterations = a->optional<int>("consistent_mass_iterations", 0, Range::in_range(0, 20));
    analysis.slip_walls = read_enum(*a, "slip_walls", kFluidSlipWalls, FluidSlipWalls::weak);
    analysis.cfl =
        a->optional<double>("cfl", 0.5, Range{0.0, analysis.consistent_mass_iterations > 0 ? 0.6 : 1.0, true, false});
    if (analysis.type == FluidAnalysisType::steady) {
      analysis.steps = a->optional<int>("steps", 1000, Range::at_least(1));
      analysis.residual_drop = a->maybe<double>("residual_drop");
      if (analysis.residual_drop && !(*analysis.residual_drop > 0.0 && *analysis.residual_drop < 1.0)) {
        a->fail("residual_drop", fmt::format("must be in (0, 1), got {}; e.g. 1e-6 stops once the "
                                             "density rate has dropped by six orders",
                                             *analysis.residual_drop));
      }
    } else if (a->has("residual_drop")) {
      a->fail("residual_drop", "applies only to analyses of type 'steady'");
    }
    if (auto r = a->optional_child("riemann")) {
      RiemannInitial riemann;
      riemann.normal = unit_vector(*r, "normal", r->vec3("normal", Vec3::UnitX()));
      riemann.position = r->required<double>("position", Range::any(), "m");
      for (auto side : {"left", "right"}) {
        const YamlNode g = r->child(side);
        GasState& state = std::string_view(side) == "left" ? riemann.left : riemann.right;
        state.density = g.required<double>("density", Range::positive(), "kg/m^3");
        state.velocity = g.vec3("velocity", Vec3::Zero());
        state.pressure = g.required<double>("pressure", Range::positive(), "Pa");
        g.finish();
      }
      r->finish();
      analysis.riemann = riemann;
    }
    if (auto i = a->optional_child("initial")) {
      if (analysis.riemann) a->fail("initial", "give either 'riemann' or 'initial', not both");
      analysis.initial = read_space_time_state(*i);
    }
    a->finish();
    fluid.analysis = analysis;
  }
  node.finish();
  return fluid;
}

}  // namespace detail

void SpaceTimeScalar::fail_non_finite(const Vec3& X, double t, double value, bool is_derivative) const {
  const double point[4] = {X.x(), X.y(), X.z(), t};
  const std::string cause = expression_.explain_non_finite(point, is_derivative ? 3 : -1);
  throw InputError(fmt::format(
      "{}: {} {} at (x, y, z) = ({:.6g}, {:.6g}, {:.6g}) m, t = {:.6g} s{}; the expression must stay "
      "finite over the run",
      where_, is_derivative ? "its rate d/dt is" : "is", std::isnan(value) ? "NaN" : (value > 0 ? "inf" : "-inf"),
      X.x(), X.y(), X.z(), t, cause.empty() ? std::string() : fmt::format(" ({}?)", cause)));
}

std::string_view to_string(FluidBoundaryType t) { return detail::name_of(detail::kFluidBoundaryTypes, t); }
std::string_view to_string(FluidSlipWalls w) { return detail::name_of(detail::kFluidSlipWalls, w); }

}  // namespace shellflow::io
