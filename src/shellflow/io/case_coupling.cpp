// The `coupling` section of a case file: a coupled fluid–shell run.
#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <charconv>
#include <cmath>

#include "shellflow/core/error.h"
#include "shellflow/io/case_names.h"
#include "shellflow/io/case_sections.h"

namespace shellflow::io::detail {

namespace {

/// `coupling.response`; the probe name is checked against the probes later (response_probe:
/// the probes section is read after this one).
ResponseSection read_response(const YamlNode& node) {
  node.expect_map();
  ResponseSection r;
  r.where = node.location();
  if (node.has("probe")) {
    r.probe = node.required<std::string>("probe");
    if (r.probe.empty()) node.fail("probe", "expected the name of a probe, got an empty string");
    r.where = node.location("probe");
  }
  if (node.has("window")) {
    const std::vector<YamlNode> items = node.list("window");
    if (items.size() != 2)
      node.fail("window", fmt::format("expected [t_start, t_end] in seconds, got a list of {} items", items.size()));
    r.t_start = items[0].as<double>();
    r.t_end = items[1].as<double>();
    if (!std::isfinite(r.t_start) || !std::isfinite(r.t_end) || !(r.t_start < r.t_end))
      node.fail("window", fmt::format("expected [t_start, t_end] with t_start < t_end (seconds), got [{}, {}]",
                                      r.t_start, r.t_end));
  }
  r.lco_cycles = node.optional<int>("lco_cycles", 5, Range::at_least(1));
  return r;
}

/// `coupling.acceleration`: `aitken`, or `{type: iqn_ils, relaxation: 0.1, ...}`.
CouplingSection::Acceleration read_acceleration(const YamlNode& parent) {
  using A = CouplingSection::Acceleration;
  A a;
  a.where = parent.location("acceleration");
  if (!parent.yaml()[std::string("acceleration")].IsMap()) {
    a.type = read_enum(parent, "acceleration", kAccelerationTypes);
    return a;
  }
  const YamlNode node = parent.child("acceleration");
  a.type = read_enum(node, "type", kAccelerationTypes);
  const bool iqn = a.type == A::Type::iqn_ils;
  if (a.type == A::Type::constant || a.type == A::Type::aitken || iqn)
    a.relaxation = node.optional<double>("relaxation", a.relaxation, Range{0.0, 2.0, true, false});
  if (iqn) {
    a.columns = node.optional<int>("columns", a.columns, Range::in_range(1, 10000));
    a.reuse = node.optional<int>("reuse", a.reuse, Range::in_range(0, 1000));
    a.filter = node.optional<double>("filter", a.filter, Range{0.0, 1.0, false, true});
  }
  node.finish();
  return a;
}

/// `coupling.identification`: `{modes: 6, pulse_width: 1e-3, gap: 4e-3, amplitude: 1e-6}`.
CouplingSection::Identification read_identification(const YamlNode& node) {
  node.expect_map();
  CouplingSection::Identification id;
  id.where = node.location();
  id.modes = node.optional<int>("modes", id.modes, Range::in_range(1, 40));
  id.pulse_width = node.optional<double>("pulse_width", 0.0, Range::positive(), "s");
  id.gap = node.optional<double>("gap", 0.0, Range::positive(), "s");
  id.amplitude = node.optional<double>("amplitude", id.amplitude, Range::open(0.0, 1e-3), "m");
  node.finish();
  return id;
}

}  // namespace

CouplingSection read_coupling(const YamlNode& node, const MeshesSection& meshes, std::vector<GroupReference>& refs) {
  CouplingSection c;
  c.where = node.location();
  c.scheme = read_enum(node, "scheme", kCouplingSchemes, CouplingSection::Scheme::staggered);
  if (auto text = node.maybe<std::string>("substeps"); text && *text != "auto") {
    int n = 0;
    const auto [end, ec] = std::from_chars(text->data(), text->data() + text->size(), n);
    if (ec != std::errc() || end != text->data() + text->size() || n < 1 || n > 100000)
      node.fail("substeps", fmt::format("expected 'auto' or a whole number of fluid steps per shell "
                                        "step from 1 to 100000, got '{}'",
                                        *text));
    c.substeps = n;
  }
  if (c.scheme == CouplingSection::Scheme::monolithic && node.has("predictor"))
    node.fail("predictor",
              "the monolithic scheme computes the loads inside the shell's Newton iteration and predicts none: "
              "remove 'predictor' (or use scheme: staggered)");
  c.predictor = read_enum(node, "predictor", kPredictors, CouplingSection::Predictor::linear);
  c.iterations = node.optional<int>("iterations", 1, Range::in_range(1, 1000));
  c.tolerance = node.optional<double>("tolerance", 1e-6, Range::open(0.0, 1.0));
  if (node.has("acceleration")) c.acceleration = read_acceleration(node);
  if (c.iterations > 1 && c.scheme == CouplingSection::Scheme::monolithic)
    node.fail("iterations",
              "the monolithic scheme solves the coupling inside the shell's Newton iteration: remove "
              "'iterations' (or use scheme: staggered)");
  if (c.iterations == 1 && node.has("acceleration") && c.acceleration.type != CouplingSection::Acceleration::Type::none)
    node.fail("acceleration", "an acceleration acts between coupling iterations: set 'iterations' above 1 (e.g. 20)");
  c.mesh_velocity = read_enum(node, "mesh_velocity", kMeshVelocities, CouplingSection::MeshVelocity::positions);
  if (auto p = node.optional_child("cavity_pressure")) c.cavity_pressure = read_time_function(*p);
  c.max_gap = node.optional<double>("max_gap", 1e-6, Range::positive(), "m");
  if (node.has("fluid_group")) {
    if (!meshes.fluid) node.fail("fluid_group", "names a group of the fluid mesh, but the case has no 'meshes.fluid'");
    c.fluid_group = node.required<std::string>("fluid_group");
    if (c.fluid_group.empty()) node.fail("fluid_group", "expected a physical group name, got an empty string");
    refs.push_back({c.fluid_group, "fluid", node.location("fluid_group")});
  }
  if (node.has("wet_normal")) c.wet_normal = unit_vector(node, "wet_normal", node.vec3("wet_normal"));
  if (auto r = node.optional_child("response"))
    c.response = read_response(*r);
  else
    c.response.where = node.location();
  if (auto id = node.optional_child("identification")) c.identification = read_identification(*id);
  node.finish();
  return c;
}

void check_coupled_case(const Case& c) {
  const CouplingSection& k = *c.coupling;
  if (!c.shell || !c.shell->analysis || c.shell->analysis->type != ShellAnalysisType::dynamic)
    throw_at(k.where,
             "a coupled run needs a shell with 'analysis: {type: dynamic}' (the shell step "
             "is time.step)");
  if (c.shell->analysis->scheme != TimeScheme::newmark)
    throw_at(c.shell->analysis->where, "a coupled run uses the Newmark scheme; remove 'scheme: midpoint'");
  const bool piston = c.fluid && c.fluid->model == FluidModelType::piston_theory;
  const bool euler = c.fluid && c.fluid->model == FluidModelType::euler;
  if (k.identification && k.iterations > 1)
    throw_at(k.identification->where,
             "an identification run prescribes the wall's motion: it has no coupling iterations; remove "
             "coupling.iterations");
  if (k.scheme == CouplingSection::Scheme::monolithic && !piston)
    throw_at(k.where,
             "scheme: monolithic puts the aerodynamic operator inside the shell's Newton "
             "iteration and is available with fluid.model: piston_theory only");
  if (piston) {
    if (k.wet_normal == Vec3::Zero())
      throw_at(k.where,
               "piston theory needs 'wet_normal': the unit vector from the shell into the "
               "flow (e.g. [0, 1, 0] for a flow above a panel in the plane y = 0)");
    if (c.motion) throw_at(c.motion->where, "piston theory has no fluid mesh to move; remove the 'motion' section");
    if (c.fluid->free_stream.mach < kPistonTheoryMinMach)
      throw_at(k.where, fmt::format("fluid.free_stream.mach {}: piston theory holds for a supersonic stream well above "
                                    "Mach 1 only (its pressure grows like 1/sqrt(M^2 - 1) without bound as M -> 1, "
                                    "where the flow over the panel is transonic); shellflow refuses M < {} (and the "
                                    "accuracy asks M >= 1.6): use fluid.model: euler",
                                    c.fluid->free_stream.mach, kPistonTheoryMinMach));
    return;
  }
  if (!c.motion)
    throw_at(k.where,
             "a coupled run on a fluid mesh needs a 'motion' section (how the fluid mesh "
             "follows the shell); see cases/panel_flutter/clamped_clamped.yaml");
  if (c.motion->prescribed)
    throw_at(c.motion->prescribed->where,
             "in a coupled run the shell moves the fluid mesh; remove "
             "'motion.prescribed'");
  if (c.motion->method != MotionMethod::space_mesh)
    throw_at(c.motion->where,
             "a coupled run moves the fluid mesh through the space mesh; use "
             "motion.method: space_mesh");
  if (k.fluid_group.empty()) throw_at(k.where, "give 'fluid_group': the fluid mesh's wet boundary (the panel's group)");
  if (std::find(c.motion->interface_groups.begin(), c.motion->interface_groups.end(), k.fluid_group) ==
      c.motion->interface_groups.end())
    throw_at(k.where, fmt::format("coupling.fluid_group '{}' must be one of motion.interface_groups (the "
                                  "boundary the shell moves); add it there",
                                  k.fluid_group));
  if (euler) {
    if (!c.fluid->analysis || c.fluid->analysis->type != FluidAnalysisType::transient)
      throw_at(k.where,
               "a coupled run with fluid.model: euler needs 'fluid.analysis' of type transient "
               "(q_dif, cfl)");
    if (c.fluid->mesh_motion)
      throw_at(c.fluid->mesh_motion->where,
               "in a coupled run the shell moves the fluid mesh; remove "
               "'fluid.mesh_motion'");
    for (const FluidBoundary& b : c.fluid->boundaries)
      if (b.group == k.fluid_group && b.type == FluidBoundaryType::no_slip_wall && b.wall_velocity)
        throw_at(b.where, fmt::format("the wet wall '{}' moves with the shell (u = the shell's velocity, paper eq. "
                                      "29); remove its 'velocity'",
                                      k.fluid_group));
  } else if (k.substeps == 0) {
    throw_at(k.where,
             "without a flow there is no stable step to choose the sub-steps from: give "
             "'substeps' as a number (e.g. 10)");
  }
}

}  // namespace shellflow::io::detail

namespace shellflow::io {

std::string_view to_string(CouplingSection::Acceleration::Type t) {
  return detail::name_of(detail::kAccelerationTypes, t);
}

std::optional<std::size_t> response_probe(const Case& c) {
  const std::string name = c.coupling ? c.coupling->response.probe : std::string();
  for (std::size_t i = 0; i < c.probes.size(); ++i)
    if (name.empty() ? c.probes[i].field == "shell.displacement" : c.probes[i].name == name) return i;
  if (name.empty()) return std::nullopt;
  std::vector<std::string> names;
  for (const Probe& p : c.probes) names.push_back(p.name);
  std::string hint;
  if (auto suggestion = closest_match(name, names)) hint = fmt::format("did you mean '{}'? ", *suggestion);
  throw_at(c.coupling->response.where,
           names.empty() ? fmt::format("no probe named '{}': the case has no probes; add one to 'probes'", name)
                         : fmt::format("no probe named '{}'; {}expected one of the probes: {}", name, hint,
                                       fmt::join(names, ", ")));
}

}  // namespace shellflow::io
