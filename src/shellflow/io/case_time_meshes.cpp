// The `meshes` and `time` sections of a case file, and the time functions that other
// sections use (`{type: ramp, ...}`, docs/case-format.md "Time functions").
#include <fmt/format.h>

#include <array>
#include <string_view>
#include <utility>

#include "shellflow/core/error.h"
#include "shellflow/io/case_sections.h"

namespace shellflow::io {

namespace fs = std::filesystem;

namespace {

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
    node.fail(file_key, fmt::format("expected a Gmsh .{} file, got '{}'", file_key, spec.as_written));
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

}  // namespace

namespace detail {

MeshesSection read_meshes(const YamlNode& root) {
  const YamlNode node = root.child("meshes");
  MeshesSection meshes;
  if (auto n = node.optional_child("fluid")) meshes.fluid = read_mesh(*n, "fluid", 1);
  if (auto n = node.optional_child("space")) meshes.space = read_mesh(*n, "space", 3);
  if (auto n = node.optional_child("shell")) meshes.shell = read_mesh(*n, "shell", 3);
  if (!meshes.fluid && !meshes.space && !meshes.shell) {
    node.fail_missing({"fluid", "space", "shell"}, "no mesh given; expected at least one of 'fluid', 'space', 'shell'");
  }
  node.finish();
  return meshes;
}

TimeSection read_time(const YamlNode& node) {
  TimeSection t;
  t.end = node.required<double>("end", Range::positive(), "s");
  t.step = node.optional<double>("step", 0.0, Range::positive(), "s");
  if (t.step > t.end) node.fail("step", fmt::format("must not exceed time.end = {} s", t.end));
  // Step counts are integers: an absurd count (or one beyond 2^63) is refused here, not met
  // as an overflow in a run.
  if (t.step > 0.0 && t.end / t.step > kMaxSteps)
    node.fail("end", fmt::format("time.end / time.step = {:.3g} steps; a run takes at most {:.0e} steps: shorten "
                                 "time.end or lengthen time.step",
                                 t.end / t.step, kMaxSteps));
  node.finish();
  return t;
}

TimeFunction read_time_function(const YamlNode& node) {
  node.expect_map();
  TimeFunction f = TimeFunction::constant(0.0);
  switch (read_enum(node, "type", kTimeFunctionTypes)) {
    case TimeFunctionType::constant:
      f = TimeFunction::constant(node.required<double>("value"));
      break;
    case TimeFunctionType::ramp:
      f = TimeFunction::ramp(node.required<double>("value"), node.required<double>("duration", Range::positive(), "s"));
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
                                        "times and {} values",
                                        times.size(), values.size()));
      }
      for (std::size_t i = 1; i < times.size(); ++i) {
        if (!(times[i] > times[i - 1])) node.fail("times", "must be strictly increasing");
      }
      f = TimeFunction::tabulated(std::move(times), std::move(values));
      break;
    }
    case TimeFunctionType::step:
      f = TimeFunction::step(node.required<double>("value"), node.required<double>("time", Range::any(), "s"));
      break;
    case TimeFunctionType::smooth_step:
      f = TimeFunction::smooth_step(node.required<double>("value"), node.required<double>("time", Range::any(), "s"),
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

const MeshSpec* MeshesSection::find(std::string_view key) const {
  if (key == "fluid") return fluid ? &*fluid : nullptr;
  if (key == "space") return space ? &*space : nullptr;
  if (key == "shell") return shell ? &*shell : nullptr;
  return nullptr;
}

std::string_view to_string(MeshFormat f) { return detail::name_of(detail::kMeshFormats, f); }

}  // namespace shellflow::io
