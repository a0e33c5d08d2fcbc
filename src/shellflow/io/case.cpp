#include "shellflow/io/case.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <map>
#include <utility>

#include "shellflow/core/error.h"
#include "shellflow/io/case_sections.h"

namespace shellflow::io {

namespace fs = std::filesystem;

namespace {

// Names of the enumerations as written in case files, indexed by enumerator value.
constexpr std::array<std::string_view, 2> kMeshFormatNames = {"geo", "msh"};
constexpr std::array<std::string_view, 6> kSupportNames = {
    "clamped", "simply_supported", "symmetry", "sliding", "prescribed", "simply_supported_hard"};
constexpr std::array<std::string_view, 6> kFluidBoundaryNames = {
    "supersonic_inflow", "supersonic_outflow", "far_field",
    "slip_wall",         "no_slip_wall",       "symmetry"};
constexpr std::array<std::string_view, 5> kComponentNames = {"x", "y", "z", "magnitude", "scalar"};
constexpr std::array<std::string_view, 4> kVectorComponentNames = {"x", "y", "z", "magnitude"};
constexpr std::array<std::string_view, 3> kLocationNames = {"point", "node", "group"};
constexpr std::array<std::string_view, 3> kReduceNames = {"mean", "min", "max"};
constexpr std::array<std::string_view, 3> kMotionMethodNames = {"space_mesh", "direct_idw",
                                                                "laplace"};
constexpr std::array<std::string_view, 2> kWeightingNames = {"plain", "area"};
enum class TimeFunctionType { constant, ramp, sine, tabulated, step, smooth_step, expression };
constexpr std::array<std::string_view, 7> kTimeFunctionNames = {
    "constant", "ramp", "sine", "tabulated", "step", "smooth_step", "expression"};
constexpr std::array<std::string_view, 6> kShellLoadNames = {
    "line", "point", "edge_couple", "pressure", "gravity", "surface"};
constexpr std::array<std::string_view, 3> kAnalysisNames = {"static", "dynamic", "modal"};
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

constexpr std::array<ProbeQuantity, 14> kProbeQuantities = {{
    {"shell", "displacement", true},
    {"shell", "velocity", true},
    {"shell", "acceleration", true},
    {"shell", "position", true},
    {"fluid", "density", false},
    {"fluid", "pressure", false},
    {"fluid", "temperature", false},
    {"fluid", "mach", false},
    {"fluid", "velocity", true},
    {"fluid", "momentum", true},
    {"fluid", "energy", false},
    {"fluid", "mesh_velocity", true},
    {"space", "displacement", true},
    {"space", "velocity", true},
}};

std::string join(const std::vector<std::string>& items, std::string_view sep) {
  return fmt::format("{}", fmt::join(items, sep));
}

/// Names used in output file names and CSV headers: [A-Za-z0-9_.-]+.
bool is_valid_name(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '-';
  });
}

std::string read_name(const YamlNode& node, std::string_view key) {
  std::string value = node.required<std::string>(key);
  if (!is_valid_name(value)) {
    node.fail(key,
              fmt::format("must contain only letters, digits, '_', '.' and '-', got '{}'", value));
  }
  return value;
}

using detail::read_group;
using detail::read_time_function;
using detail::unit_vector;

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

void require_mesh(const YamlNode& section, const MeshesSection& meshes, std::string_view mesh) {
  if (!meshes.find(mesh)) {
    section.fail(
        fmt::format("needs a {} mesh; expected 'meshes.{}' with 'geo' or 'msh'", mesh, mesh));
  }
}

// ---- sections -------------------------------------------------------------------------------

MeshSpec read_mesh(const YamlNode& node, std::string_view key, int default_order) {
  MeshSpec spec;
  spec.key = std::string(key);
  spec.where = node.location();
  const bool geo = node.has("geo");
  const bool msh = node.has("msh");
  if (geo && msh) node.fail("both 'geo' and 'msh' given; expected exactly one of them");
  if (!geo && !msh) node.fail_missing({"geo", "msh"});
  spec.format = geo ? MeshFormat::geo : MeshFormat::msh;
  const std::string_view file_key = geo ? "geo" : "msh";
  spec.as_written = node.required<std::string>(file_key);
  const std::string extension = fs::path(spec.as_written).extension().string();
  if (extension != fmt::format(".{}", file_key)) {
    node.fail(file_key,
              fmt::format("expected a Gmsh .{} file, got '{}'", file_key, spec.as_written));
  }
  spec.file = node.input_file(file_key);
  if (geo) {
    spec.order = node.optional<int>("order", default_order, Range::in_range(1, 3));
    spec.size_factor = node.optional<double>("size_factor", 1.0, Range::positive());
  } else {
    for (const std::string_view k : {"order", "size_factor"}) {
      if (node.has(k)) {
        node.fail(k, "applies only to meshes given by 'geo'; a .msh file is used as it is");
      }
    }
    spec.order = 0;
  }
  node.finish();
  return spec;
}

MeshesSection read_meshes(const YamlNode& root) {
  const YamlNode node = root.child("meshes");
  MeshesSection meshes;
  if (auto n = node.optional_child("fluid")) meshes.fluid = read_mesh(*n, "fluid", 1);
  if (auto n = node.optional_child("space")) meshes.space = read_mesh(*n, "space", 3);
  if (auto n = node.optional_child("shell")) meshes.shell = read_mesh(*n, "shell", 3);
  if (!meshes.fluid && !meshes.space && !meshes.shell) {
    node.fail_missing({"fluid", "space", "shell"},
                      "no mesh given; expected at least one of 'fluid', 'space', 'shell'");
  }
  node.finish();
  return meshes;
}

/// A time function: {type: constant|ramp|sine|tabulated, ...} (docs/case-format.md).
ShellSection read_shell(const YamlNode& node, std::vector<GroupReference>& refs) {
  ShellSection shell;
  shell.thickness = node.required<double>("thickness", Range::positive(), "m");

  const YamlNode material = node.child("material");
  shell.material.young_modulus =
      material.required<double>("young_modulus", Range::positive(), "Pa");
  shell.material.poisson_ratio = material.required<double>("poisson_ratio", Range::open(-1, 0.5));
  shell.material.density = material.required<double>("density", Range::non_negative(), "kg/m^3");
  material.finish();

  for (const YamlNode& item : node.optional_list("supports")) {
    item.expect_map();
    Support s;
    s.where = item.location();
    s.group = read_group(item, "shell", refs);
    s.type = item.enumeration<SupportType>("type", kSupportNames);
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
        item.fail("a prescribed support needs 'displacement' [x, y, z] and/or 'rotation_axis' "
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
    load.type = item.enumeration<ShellLoadType>("type", kShellLoadNames);
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
      case ShellLoadType::gravity: load.vector = item.vec3("acceleration"); break;
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
    const auto type = a->choice("type", kAnalysisNames);
    analysis.type = type == "static"    ? ShellAnalysisType::static_load
                    : type == "dynamic" ? ShellAnalysisType::dynamic
                                        : ShellAnalysisType::modal;
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
      const std::string control =
          a->choice("control", {"load", "displacement", "arc_length"}, "load");
      if (control == "displacement") {
        analysis.control = PathControl::displacement;
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
      } else if (control == "arc_length") {
        analysis.control = PathControl::arc_length;
        analysis.initial_load_increment =
            a->optional<double>("initial_load_increment", 0.1, Range::positive());
        analysis.final_load_factor = a->optional<double>("final_load_factor", 1.0, Range::positive());
      }
      for (const Support& support : shell.supports) {
        if (support.type == SupportType::prescribed && analysis.control != PathControl::load) {
          a->fail("control", fmt::format("the prescribed support {} (line {}) moves with the load factor, "
                                         "which control: {} varies inside a step; use control: load",
                                         support.where.key_path, support.where.line, control));
        }
      }
    } else if (analysis.type == ShellAnalysisType::dynamic) {
      if (!(shell.material.density > 0.0)) {
        a->fail("type", "a dynamic analysis needs the shell's mass; set shell.material.density > 0");
      }
      if (auto f = a->optional_child("load_function")) analysis.load_function = read_time_function(*f);
      analysis.mass_damping = a->optional<double>("mass_damping", 0.0, Range::non_negative(), "1/s");
      analysis.scheme = a->choice("scheme", {"newmark", "midpoint"}, "newmark") == "midpoint"
                            ? TimeScheme::midpoint
                            : TimeScheme::newmark;
    }
    if (analysis.type != ShellAnalysisType::modal)
      analysis.modified_newton = a->choice("newton", {"full", "modified"}, "full") == "modified";
    if (analysis.modified_newton && analysis.type == ShellAnalysisType::static_load &&
        analysis.control != PathControl::load) {
      a->fail("newton", "'modified' applies to load control and dynamics; displacement control "
                        "and arc length use full Newton");
    }
    a->finish();
    shell.analysis = std::move(analysis);
  }
  node.finish();
  return shell;
}

FluidSection read_fluid(const YamlNode& node, std::vector<GroupReference>& refs) {
  FluidSection fluid;
  fluid.model = node.choice("model", {"euler", "piston_theory"}, "euler") == "piston_theory"
                    ? FluidModelType::piston_theory
                    : FluidModelType::euler;
  if (fluid.model == FluidModelType::piston_theory) {
    for (const std::string_view key : {"boundaries", "mesh_motion", "analysis"})
      if (node.has(key))
        node.fail(key, "piston theory computes the loads from the shell's motion, without a fluid "
                       "mesh; remove it (or use model: euler)");
  }
  if (auto gas = node.optional_child("gas")) {
    fluid.gas.gamma = gas->optional<double>("gamma", 1.4, Range::greater_than(1));
    fluid.gas.gas_constant =
        gas->optional<double>("gas_constant", 287.05, Range::positive(), "J/(kg K)");
    if (auto v = gas->optional_child("viscosity")) {
      Viscosity& mu = fluid.gas.viscosity;
      const std::string law = v->choice("law", {"none", "constant", "sutherland"});
      mu.law = law == "constant"     ? ViscosityLaw::constant
               : law == "sutherland" ? ViscosityLaw::sutherland
                                     : ViscosityLaw::none;
      mu.mu_ref = v->optional<double>("mu_ref", mu.mu_ref, Range::positive(), "Pa s");
      mu.prandtl = v->optional<double>("prandtl", mu.prandtl, Range::positive());
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
  fluid.free_stream.direction =
      unit_vector(stream, "direction", stream.vec3("direction", Vec3::UnitX()));
  stream.finish();

  std::map<std::string, int> first_line;  // group -> line of its first boundary condition
  for (const YamlNode& item : node.optional_list("boundaries")) {
    item.expect_map();
    FluidBoundary b;
    b.where = item.location();
    b.group = read_group(item, "fluid", refs);
    b.type = item.enumeration<FluidBoundaryType>("type", kFluidBoundaryNames);
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
      b.wall_velocity = item.vec3("velocity", Vec3::Zero());
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
    analysis.type = a->choice("type", {"transient", "steady"}) == "steady"
                        ? FluidAnalysisType::steady
                        : FluidAnalysisType::transient;
    analysis.q_dif = a->optional<double>("q_dif", 0.0, Range::non_negative());
    analysis.consistent_mass_iterations =
        a->optional<int>("consistent_mass_iterations", 0, Range::in_range(0, 20));
    analysis.cfl = a->optional<double>(
        "cfl", 0.5,
        Range{0.0, analysis.consistent_mass_iterations > 0 ? 0.6 : 1.0, true, false});
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

Probe read_probe(const YamlNode& item, const MeshesSection& meshes,
                 std::vector<GroupReference>& refs) {
  item.expect_map();
  Probe p;
  p.where = item.location();
  p.name = read_name(item, "name");
  if (p.name == "time") {
    item.fail("name",
              "'time' is reserved for the time column of probes.csv; expected another "
              "name");
  }

  p.field = item.required<std::string>("field");
  const auto dot = p.field.find('.');
  p.mesh = p.field.substr(0, dot);
  p.quantity = dot == std::string::npos ? std::string() : p.field.substr(dot + 1);
  if (dot == std::string::npos ||
      std::find(std::begin(kMeshKeys), std::end(kMeshKeys), p.mesh) == std::end(kMeshKeys)) {
    item.fail("field", fmt::format("expected 'MESH.QUANTITY' with MESH one of fluid, space, "
                                   "shell, got '{}'",
                                   p.field));
  }
  const ProbeQuantity* quantity = nullptr;
  std::vector<std::string> fields;
  for (const auto& q : probe_quantities()) {
    if (q.mesh != p.mesh) continue;
    fields.push_back(fmt::format("{}.{}", q.mesh, q.quantity));
    if (q.quantity == p.quantity) quantity = &q;
  }
  if (!quantity) {
    std::string what = fmt::format("unknown field '{}'; ", p.field);
    if (auto suggestion = closest_match(p.field, fields)) {
      what += fmt::format("did you mean '{}'? (one of: {})", *suggestion, join(fields, ", "));
    } else {
      what += fmt::format("expected one of: {}", join(fields, ", "));
    }
    item.fail("field", what);
  }
  if (!meshes.find(p.mesh)) {
    item.fail("field",
              fmt::format("the case has no {} mesh; expected 'meshes.{}'", p.mesh, p.mesh));
  }

  if (quantity->is_vector) {
    p.component = item.enumeration<ProbeComponent>("component", kVectorComponentNames,
                                                   ProbeComponent::magnitude);
  } else {
    p.component = ProbeComponent::scalar;
    if (item.has("component")) {
      item.fail("component",
                fmt::format("applies only to vector fields; '{}' is a scalar", p.field));
    }
  }

  const int given = int{item.has("point")} + int{item.has("node")} + int{item.has("group")};
  if (given == 0) item.fail_missing({"point", "node", "group"});
  if (given > 1) item.fail("give only one of 'point', 'node', 'group'");
  if (item.has("point")) {
    p.location = ProbeLocation::point;
    p.point = item.vec3("point");
  } else if (item.has("node")) {
    p.location = ProbeLocation::node;
    p.node = item.required<Index>("node", Range::non_negative());
  } else {
    p.location = ProbeLocation::group;
    p.group = read_group(item, p.mesh, refs);
  }
  if (p.location == ProbeLocation::group) {
    p.reduce = item.enumeration<ProbeReduce>("reduce", kReduceNames, ProbeReduce::mean);
  } else if (item.has("reduce")) {
    item.fail("reduce", "applies only to probes on a 'group'");
  }
  if (auto r = item.optional_child("reference")) p.reference = detail::read_probe_reference(*r);
  item.finish();
  return p;
}

std::vector<Probe> read_probes(const YamlNode& root, const MeshesSection& meshes,
                               std::vector<GroupReference>& refs) {
  std::vector<Probe> probes;
  std::map<std::string, int> first_line;  // name -> line where it was first used
  for (const YamlNode& item : root.optional_list("probes")) {
    Probe p = read_probe(item, meshes, refs);
    const auto [it, inserted] = first_line.emplace(p.name, item.location("name").line);
    if (!inserted) {
      item.fail("name", fmt::format("duplicate probe name '{}' (first used at line {}); "
                                    "expected unique names",
                                    p.name, it->second));
    }
    probes.push_back(std::move(p));
  }
  return probes;
}

std::vector<std::string> read_group_list(const YamlNode& node, std::string_view key,
                                         const std::vector<std::string_view>& meshes,
                                         std::vector<GroupReference>& refs) {
  std::vector<std::string> groups;
  for (const YamlNode& item : node.optional_list(key)) {
    std::string group = item.as<std::string>();
    if (group.empty()) item.fail("expected a physical group name, got an empty string");
    for (auto mesh : meshes) refs.push_back({group, std::string(mesh), item.location()});
    groups.push_back(std::move(group));
  }
  return groups;
}

MotionSection read_motion(const YamlNode& node, const MeshesSection& meshes,
                          std::vector<GroupReference>& refs) {
  MotionSection m;
  m.where = node.location();
  m.method = node.enumeration<MotionMethod>("method", kMotionMethodNames, MotionMethod::space_mesh);
  if (m.method == MotionMethod::space_mesh) require_mesh(node, meshes, "space");
  std::vector<std::string_view> group_meshes{"fluid"};
  if (m.method == MotionMethod::space_mesh) group_meshes.push_back("space");
  m.interface_groups = read_group_list(node, "interface_groups", group_meshes, refs);
  if (m.interface_groups.empty()) {
    node.fail("interface_groups", "expected a list of the moving boundary's physical groups");
  }
  m.fixed_groups = read_group_list(node, "fixed_groups", group_meshes, refs);
  m.sliding_groups = read_group_list(node, "sliding_groups", group_meshes, refs);
  m.interface_exponent = node.optional<double>("interface_exponent", 4.0, Range::positive());
  m.fixed_exponent = node.optional<double>("fixed_exponent", 4.0, Range::positive());
  m.weighting = node.enumeration<MotionWeighting>("weighting", kWeightingNames, MotionWeighting::plain);
  if (auto p = node.optional_child("prescribed")) {
    PanelModesSpec spec;
    spec.where = p->location();
    const std::string type = p->choice("type", {"panel_modes"});
    (void)type;
    spec.leading_edge = p->vec3("leading_edge");
    spec.direction = unit_vector(*p, "direction", p->vec3("direction", Vec3::UnitX()));
    spec.length = p->required<double>("length", Range::positive(), "m");
    spec.normal = unit_vector(*p, "normal", p->vec3("normal", Vec3::UnitY()));
    for (const YamlNode& item : p->list("modes")) {
      item.expect_map();
      PanelModesSpec::Mode mode;
      mode.wave_number = item.optional<int>("wave_number", 1, Range::at_least(1));
      mode.amplitude = read_time_function(item.child("amplitude"));
      item.finish();
      spec.modes.push_back(std::move(mode));
    }
    p->finish();
    m.prescribed = std::move(spec);
  }
  node.finish();
  return m;
}

TimeSection read_time(const YamlNode& node) {
  TimeSection t;
  t.end = node.required<double>("end", Range::positive(), "s");
  t.step = node.optional<double>("step", 0.0, Range::positive(), "s");
  if (t.step > t.end) node.fail("step", fmt::format("must not exceed time.end = {} s", t.end));
  node.finish();
  return t;
}

OutputSection read_output(const YamlNode& root, const std::string& case_name) {
  OutputSection out;
  out.directory = fs::path("out") / case_name;
  if (auto node = root.optional_child("output")) {
    if (auto dir = node->maybe<std::string>("directory")) {
      if (dir->empty()) node->fail("directory", "expected a directory name, got an empty string");
      out.directory = *dir;
    }
    out.every = node->optional<int>("every", 1, Range::at_least(1));
    out.checkpoint_every = node->optional<long>("checkpoint_every", 0, Range::non_negative());
    const std::string stress =
        node->choice("shell_stress", {"cauchy", "second_piola_kirchhoff", "none"}, "cauchy");
    out.shell_stress = stress == "cauchy" ? OutputSection::ShellStress::cauchy
                       : stress == "none" ? OutputSection::ShellStress::none
                                          : OutputSection::ShellStress::second_piola_kirchhoff;
    node->finish();
  }
  return out;
}

Case read_case(const YamlNode& root) {
  Case c;
  c.file = root.file();
  c.name = read_name(root, "name");
  c.description = root.optional<std::string>("description", {});
  c.meshes = read_meshes(root);
  if (auto node = root.optional_child("shell")) {
    require_mesh(*node, c.meshes, "shell");
    c.shell = read_shell(*node, c.group_references);
  }
  if (auto node = root.optional_child("fluid")) {
    c.fluid = read_fluid(*node, c.group_references);
    if (c.fluid->model == FluidModelType::euler) require_mesh(*node, c.meshes, "fluid");
  }
  if (auto node = root.optional_child("motion")) {
    require_mesh(*node, c.meshes, "fluid");
    c.motion = read_motion(*node, c.meshes, c.group_references);
  }
  if (auto node = root.optional_child("time")) c.time = read_time(*node);
  if (auto node = root.optional_child("coupling")) {
    c.coupling = detail::read_coupling(*node, c.meshes, c.group_references);
    detail::check_coupled_case(c);
  }
  if (c.shell && c.shell->analysis && c.shell->analysis->type == ShellAnalysisType::dynamic &&
      !(c.time && c.time->step > 0)) {
    throw_at(c.shell->analysis->where, "a dynamic analysis needs a 'time' section (end, step)");
  }
  if (c.motion && !(c.time && c.time->step > 0)) {
    throw_at(c.motion->where, "a mesh-motion run needs a 'time' section (end, step)");
  }
  if (c.motion && !c.coupling && !c.motion->prescribed) {
    throw_at(c.motion->where, "a mesh-motion run without a 'coupling' section needs 'prescribed' (the "
                              "boundary motion); add it, or a 'coupling' section to let the shell drive it");
  }
  if (c.fluid && c.fluid->analysis && c.fluid->analysis->type == FluidAnalysisType::transient &&
      !c.time) {
    throw_at(c.fluid->analysis->where,
             "a transient flow analysis needs a 'time' section (end; the step follows from cfl)");
  }
  if (c.fluid && c.fluid->mesh_motion) {
    if (c.motion) {
      throw_at(c.fluid->mesh_motion->where,
               "the fluid mesh is moved either by 'fluid.mesh_motion' (prescribed) or by the "
               "'motion' section (space mesh), not both; remove one");
    }
    for (const FluidBoundary& b : c.fluid->boundaries) {
      if (b.type == FluidBoundaryType::no_slip_wall && b.wall_velocity != Vec3::Zero()) {
        throw_at(b.where, "on a moving mesh a no-slip wall moves with the mesh; remove its "
                          "'velocity' or the 'mesh_motion'");
      }
    }
    if (c.fluid->analysis && c.fluid->analysis->type == FluidAnalysisType::steady) {
      throw_at(c.fluid->mesh_motion->where,
               "a steady (local time stepping) analysis needs a fixed mesh; use type: transient "
               "or remove 'mesh_motion'");
    }
  }
  if (!c.coupling) {
    int solvers = (c.motion ? 1 : 0) + (c.shell && c.shell->analysis ? 1 : 0) +
                  (c.fluid && c.fluid->analysis ? 1 : 0);
    if (solvers > 1) {
      throw_at(c.motion ? c.motion->where : c.fluid->analysis->where,
               "combining mesh motion, a shell analysis and a flow analysis is a coupled run: "
               "add a 'coupling' section (docs/case-format.md), or keep one of them");
    }
  }

  c.probes = read_probes(root, c.meshes, c.group_references);
  c.output = read_output(root, c.name);
  if (c.coupling) (void)response_probe(c);  // an unknown coupling.response.probe, before anything runs
  if (auto node = root.optional_child("study")) c.study = detail::read_study(*node, c);
  root.finish();
  c.digests = case_digests(root.yaml());
  std::stable_sort(
      c.group_references.begin(), c.group_references.end(),
      [](const GroupReference& a, const GroupReference& b) { return a.where.line < b.where.line; });
  return c;
}

}  // namespace

namespace detail {

std::string read_group(const YamlNode& node, std::string_view mesh,
                       std::vector<GroupReference>& refs) {
  std::string group = node.required<std::string>("group");
  if (group.empty()) node.fail("group", "expected a physical group name, got an empty string");
  refs.push_back({group, std::string(mesh), node.location("group")});
  return group;
}

Vec3 unit_vector(const YamlNode& node, std::string_view key, const Vec3& v) {
  const double n = v.norm();
  if (!(n > 0.0)) node.fail(key, "must be a non-zero vector [x, y, z], got [0, 0, 0]");
  return v / n;
}

TimeFunction read_time_function(const YamlNode& node) {
  node.expect_map();
  TimeFunction f = TimeFunction::constant(0.0);
  switch (node.enumeration<TimeFunctionType>("type", kTimeFunctionNames)) {
    case TimeFunctionType::constant: f = TimeFunction::constant(node.required<double>("value")); break;
    case TimeFunctionType::ramp:
      f = TimeFunction::ramp(node.required<double>("value"),
                             node.required<double>("duration", Range::positive(), "s"));
      break;
    case TimeFunctionType::sine:
      f = TimeFunction::sine(node.required<double>("value"),
                             node.required<double>("frequency", Range::positive(), "Hz"),
                             node.optional<double>("phase", 0.0, Range::any(), "rad"));
      break;
    case TimeFunctionType::tabulated: {
      std::vector<double> times, values;
      for (const YamlNode& t : node.list("times")) times.push_back(t.as<double>());
      for (const YamlNode& v : node.list("values")) values.push_back(v.as<double>());
      if (times.empty() || times.size() != values.size()) {
        node.fail("values", fmt::format("expected as many values as times (at least one), got {} "
                                        "times and {} values", times.size(), values.size()));
      }
      for (std::size_t i = 1; i < times.size(); ++i) {
        if (!(times[i] > times[i - 1])) node.fail("times", "must be strictly increasing");
      }
      f = TimeFunction::tabulated(std::move(times), std::move(values));
      break;
    }
    case TimeFunctionType::step:
      f = TimeFunction::step(node.required<double>("value"),
                             node.required<double>("time", Range::any(), "s"));
      break;
    case TimeFunctionType::smooth_step:
      f = TimeFunction::smooth_step(node.required<double>("value"),
                                    node.required<double>("time", Range::any(), "s"),
                                    node.required<double>("duration", Range::positive(), "s"));
      break;
    case TimeFunctionType::expression: {
      const std::string text = node.required<std::string>("value");
      try {
        f = TimeFunction::expression(text);
      } catch (const InputError& e) {
        node.fail("value", e.what());  // FILE:LINE: ....value: expression "...": column N: ...
      }
      break;
    }
  }
  node.finish();
  // Checked where it is evaluated: a value that is not finite names this key and the time.
  return f.named(node.location().prefix());
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

const MeshSpec* MeshesSection::find(std::string_view key) const {
  if (key == "fluid") return fluid ? &*fluid : nullptr;
  if (key == "space") return space ? &*space : nullptr;
  if (key == "shell") return shell ? &*shell : nullptr;
  return nullptr;
}

std::span<const ProbeQuantity> probe_quantities() { return kProbeQuantities; }

Case read_case(const fs::path& file, std::span<const KeyOverride> overrides) {
  return read_case(YamlNode::load_file(file, overrides));
}

Case read_case_string(std::string_view text, const fs::path& file, std::span<const KeyOverride> overrides) {
  return read_case(YamlNode::load_string(text, file, overrides));
}

void check_physical_groups(const Case& c, const GroupNamesOfMesh& groups_of_mesh) {
  std::map<std::string, std::vector<std::string>, std::less<>> groups;
  for (const GroupReference& ref : c.group_references) {
    auto it = groups.find(ref.mesh);
    if (it == groups.end()) it = groups.emplace(ref.mesh, groups_of_mesh(ref.mesh)).first;
    const std::vector<std::string>& available = it->second;
    if (std::find(available.begin(), available.end(), ref.group) != available.end()) continue;

    const MeshSpec* mesh = c.meshes.find(ref.mesh);
    std::string what =
        fmt::format("physical group '{}' not found in mesh '{}'", ref.group, ref.mesh);
    if (mesh) what += fmt::format(" ({})", mesh->as_written);
    if (available.empty()) {
      what += "; the mesh has no physical groups";
    } else {
      if (auto suggestion = closest_match(ref.group, available)) {
        what +=
            fmt::format("; did you mean '{}'? available: {}", *suggestion, join(available, ", "));
      } else {
        what += fmt::format("; available: {}", join(available, ", "));
      }
    }
    throw_at(ref.where, what);
  }
}

std::string_view to_string(MeshFormat f) { return kMeshFormatNames[static_cast<std::size_t>(f)]; }
std::string_view to_string(SupportType t) { return kSupportNames[static_cast<std::size_t>(t)]; }
std::string_view to_string(FluidBoundaryType t) {
  return kFluidBoundaryNames[static_cast<std::size_t>(t)];
}
std::string_view to_string(ProbeComponent c) {
  return kComponentNames[static_cast<std::size_t>(c)];
}
std::string_view to_string(ProbeLocation l) { return kLocationNames[static_cast<std::size_t>(l)]; }
std::string_view to_string(ShellLoadType t) { return kShellLoadNames[static_cast<std::size_t>(t)]; }
std::string_view to_string(MotionMethod m) {
  return kMotionMethodNames[static_cast<std::size_t>(m)];
}
std::string_view to_string(MotionWeighting w) { return kWeightingNames[static_cast<std::size_t>(w)]; }
std::string_view to_string(ProbeReduce r) { return kReduceNames[static_cast<std::size_t>(r)]; }

}  // namespace shellflow::io
