// The `shell` section of a case file: thickness, material, supports, loads and the analysis.
#include <fmt/format.h>

#include <array>
#include <cmath>
#include <string_view>
#include <utility>

#include "shellflow/core/error.h"
#include "shellflow/io/case_sections.h"

namespace shellflow::io {

namespace {

// Keys of the static and dynamic shell analyses with the types they belong to, refused by
// name in a modal one: a modal analysis follows no load path and no time, and the message
// says where the key belongs rather than "unknown key".
constexpr std::array<std::pair<std::string_view, std::string_view>, 10> kLoadPathKeys = {{
    {"steps", "static"},
    {"control", "static"},
    {"controlled", "static"},
    {"final_value", "static"},
    {"initial_load_increment", "static"},
    {"final_load_factor", "static"},
    {"load_function", "dynamic"},
    {"mass_damping", "dynamic"},
    {"scheme", "dynamic"},
    {"newton", "static' or 'dynamic"},
}};
constexpr std::array<std::string_view, 3> kModalKeys = {"modes", "tolerance", "max_iterations"};

constexpr double kMinPoissonRatio = -0.9, kMaxPoissonRatio = 0.49, kMaxWaveSpeed = 1e6;

}  // namespace

/// Data the model cannot stand although each value is in its range: near-singular material
/// laws (docs/case-format.md, "Validity limits").
void check_material(const YamlNode& material, const Material& m) {
  const double nu = m.poisson_ratio;
  if (nu <= kMinPoissonRatio || nu > kMaxPoissonRatio)
    material.fail("poisson_ratio",
                  fmt::format("{} is too close to {}: the 3-D law of the 7-parameter shell becomes near-singular "
                              "({} = {:.3g}); shellflow accepts {} < nu <= {}",
                              nu, nu < 0 ? "-1" : "0.5", nu < 0 ? "1 + nu" : "1 - 2 nu", nu < 0 ? 1 + nu : 1 - 2 * nu,
                              kMinPoissonRatio, kMaxPoissonRatio));
  // A solid's wave speed sqrt(E / rho) is a few km/s (steel 5.1e3 m/s, beryllium 1.3e4): a
  // thousand times more is a unit slip, and a near-singular mass matrix.
  if (m.density > 0.0 && std::sqrt(m.young_modulus / m.density) > kMaxWaveSpeed)
    material.fail("density",
                  fmt::format("{} kg/m^3 with young_modulus {} Pa gives a wave speed sqrt(E/rho) = {:.3g} "
                              "m/s, above {:.0e} m/s (steel: 5.1e3): a near-singular mass matrix; check the "
                              "units (kg/m^3, Pa)",
                              m.density, m.young_modulus, std::sqrt(m.young_modulus / m.density), kMaxWaveSpeed));
}

namespace detail {

ShellSection read_shell(const YamlNode& node, std::vector<GroupReference>& refs) {
  ShellSection shell;
  shell.thickness = node.required<double>("thickness", Range::positive(), "m");

  const YamlNode material = node.child("material");
  shell.material.young_modulus = material.required<double>("young_modulus", Range::positive(), "Pa");
  shell.material.poisson_ratio = material.required<double>("poisson_ratio", Range::open(-1, 0.5));
  shell.material.density = material.required<double>("density", Range::non_negative(), "kg/m^3");
  check_material(material, shell.material);
  material.finish();

  for (const YamlNode& item : node.optional_list("supports")) {
    item.expect_map();
    Support s;
    s.where = item.location();
    s.group = read_group(item, "shell", refs);
    s.type = read_enum(item, "type", kSupportTypes);
    if (s.type == SupportType::sliding) {
      s.direction = unit_vector(item, "direction", item.vec3("direction"));
      s.clamp_director = item.optional<bool>("clamp_director", true);
    } else {
      if (item.has("direction")) item.fail("direction", "applies only to supports of type 'sliding'");
      if (item.has("clamp_director")) {
        item.fail("clamp_director", "applies only to supports of type 'sliding'");
      }
    }
    if (s.type == SupportType::symmetry) {
      s.normal = unit_vector(item, "normal", item.vec3("normal"));
    } else if (item.has("normal")) {
      item.fail("normal", "applies only to supports of type 'symmetry'");
    }
    if (s.type == SupportType::prescribed) {
      if (!item.has("displacement") && !item.has("rotation_axis")) {
        item.fail(
            "a prescribed support needs 'displacement' [x, y, z] and/or 'rotation_axis' "
            "with 'rotation_angle'");
      }
      if (item.has("displacement")) s.displacement = item.vec3("displacement");
      if (auto f = item.optional_child("history")) s.displacement_history = read_time_function(*f);
      if (item.has("rotation_axis")) {
        s.rotation_axis = unit_vector(item, "rotation_axis", item.vec3("rotation_axis"));
        s.rotation_angle = read_time_function(item.child("rotation_angle"));
      } else if (item.has("rotation_angle")) {
        item.fail("rotation_angle", "needs 'rotation_axis' [x, y, z] beside it");
      }
    } else {
      for (const char* key : {"displacement", "history", "rotation_axis", "rotation_angle"}) {
        if (item.has(key)) item.fail(key, "applies only to supports of type 'prescribed'");
      }
    }
    item.finish();
    shell.supports.push_back(std::move(s));
  }
  for (const YamlNode& item : node.optional_list("loads")) {
    item.expect_map();
    ShellLoad load;
    load.where = item.location();
    load.type = read_enum(item, "type", kShellLoadTypes);
    switch (load.type) {
      case ShellLoadType::line:
        load.group = read_group(item, "shell", refs);
        load.vector = item.vec3("force_per_length");
        break;
      case ShellLoadType::point:
        load.point = item.vec3("point");
        load.vector = item.vec3("force");
        break;
      case ShellLoadType::edge_couple:
        load.group = read_group(item, "shell", refs);
        load.vector = unit_vector(item, "axis", item.vec3("axis"));
        load.value = item.required<double>("moment_per_length");
        break;
      case ShellLoadType::pressure:
        if (item.has("group")) load.group = read_group(item, "shell", refs);
        load.value = item.required<double>("pressure");
        break;
      case ShellLoadType::gravity:
        load.vector = item.vec3("acceleration");
        break;
      case ShellLoadType::surface:
        if (item.has("group")) load.group = read_group(item, "shell", refs);
        load.vector = item.vec3("traction");
        break;
    }
    item.finish();
    shell.loads.push_back(std::move(load));
  }
  if (auto a = node.optional_child("analysis")) {
    ShellAnalysis analysis;
    analysis.where = a->location();
    analysis.type = read_enum(*a, "type", kShellAnalysisTypes);
    if (analysis.type == ShellAnalysisType::modal) {
      for (const auto& [key, types] : kLoadPathKeys) {
        if (a->has(key)) {
          a->fail(key, fmt::format("applies only to analyses of type '{}'; a modal analysis takes "
                                   "'modes', 'tolerance' and 'max_iterations'",
                                   types));
        }
      }
      if (!(shell.material.density > 0.0)) {
        a->fail("type", "a modal analysis needs the shell's mass; set shell.material.density > 0");
      }
      analysis.modes = a->optional<int>("modes", 10, Range::in_range(1, 200));
      analysis.modal_tolerance = a->optional<double>("tolerance", 1e-8, Range::open(0.0, 1.0));
      analysis.modal_max_iterations = a->optional<int>("max_iterations", 300, Range::at_least(1));
    } else {
      for (const std::string_view key : kModalKeys)
        if (a->has(key)) a->fail(key, "applies only to analyses of type 'modal'");
    }
    if (analysis.type == ShellAnalysisType::static_load) {
      analysis.steps = a->optional<int>("steps", 10, Range::at_least(1));
      analysis.control = read_enum(*a, "control", kPathControls, PathControl::load);
      if (analysis.control == PathControl::displacement) {
        const YamlNode d = a->child("controlled");
        if (d.has("group") == d.has("node")) {
          d.fail("expected exactly one of 'group' (its mean displacement) and 'node'");
        }
        if (d.has("group")) analysis.controlled_group = read_group(d, "shell", refs);
        if (d.has("node")) analysis.controlled_node = d.required<int>("node", Range::at_least(0));
        const std::string axis = d.choice("component", {"x", "y", "z"});
        analysis.controlled_component = axis == "x" ? 0 : axis == "y" ? 1 : 2;
        d.finish();
        analysis.final_displacement = a->required<double>("final_value", Range::any(), "m");
      } else if (analysis.control == PathControl::arc_length) {
        analysis.initial_load_increment = a->optional<double>("initial_load_increment", 0.1, Range::positive());
        analysis.final_load_factor = a->optional<double>("final_load_factor", 1.0, Range::positive());
      }
      for (const Support& support : shell.supports) {
        if (support.type == SupportType::prescribed && analysis.control != PathControl::load) {
          a->fail("control",
                  fmt::format("the prescribed support {} (line {}) moves with the load factor, "
                              "which control: {} varies inside a step; use control: load",
                              support.where.key_path, support.where.line, name_of(kPathControls, analysis.control)));
        }
      }
    } else if (analysis.type == ShellAnalysisType::dynamic) {
      if (!(shell.material.density > 0.0)) {
        a->fail("type", "a dynamic analysis needs the shell's mass; set shell.material.density > 0");
      }
      if (auto f = a->optional_child("load_function")) analysis.load_function = read_time_function(*f);
      analysis.mass_damping = a->optional<double>("mass_damping", 0.0, Range::non_negative(), "1/s");
      analysis.scheme = read_enum(*a, "scheme", kTimeSchemes, TimeScheme::newmark);
    }
    if (analysis.type != ShellAnalysisType::modal)
      analysis.modified_newton = a->choice("newton", {"full", "modified"}, "full") == "modified";
    if (analysis.modified_newton && analysis.type == ShellAnalysisType::static_load &&
        analysis.control != PathControl::load) {
      a->fail("newton",
              "'modified' applies to load control and dynamics; displacement control "
              "and arc length use full Newton");
    }
    a->finish();
    shell.analysis = std::move(analysis);
  }
  node.finish();
  return shell;
}

}  // namespace detail

std::string_view to_string(SupportType t) { return detail::name_of(detail::kSupportTypes, t); }
std::string_view to_string(ShellLoadType t) { return detail::name_of(detail::kShellLoadTypes, t); }

}  // namespace shellflow::io
