// The `study` section of a case file: a parameter study of a coupled case (`shellflow study`).
#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <cmath>

#include "shellflow/core/error.h"
#include "shellflow/io/case_sections.h"

namespace shellflow::io {

std::string_view to_string(StudySection::Parameter p) { return detail::name_of(detail::kStudyParameters, p); }

namespace detail {

StudySection read_study(const YamlNode& node, const Case& c) {
  StudySection s;
  s.where = node.location();
  node.expect_map();
  s.parameter = read_enum(node, "parameter", kStudyParameters);
  const auto range = node.list("range");
  if (range.size() != 2) node.fail("range", fmt::format("expected [lo, hi], got a list of {} values", range.size()));
  s.lo = range[0].as<double>();
  s.hi = range[1].as<double>();
  if (!(std::isfinite(s.lo) && std::isfinite(s.hi) && s.lo < s.hi))
    node.fail("range", fmt::format("expected lo < hi, got [{}, {}]", s.lo, s.hi));
  const bool mach = s.parameter == StudySection::Parameter::mach;
  if (mach && !(s.lo > 1.0) && (c.fluid && c.fluid->model == FluidModelType::piston_theory))
    node.fail("range", fmt::format("piston theory needs Mach > 1; the range starts at {}", s.lo));
  if (!mach && !(s.lo > 0.0))
    node.fail("range", fmt::format("the {} must stay > 0; the range starts at {}", to_string(s.parameter), s.lo));
  s.points = node.optional<int>("points", 5, Range::in_range(2, 200));
  s.tolerance = node.optional<double>("tolerance", (s.hi - s.lo) / 100.0, Range::positive());
  s.max_refinements = node.optional<int>("max_refinements", 12, Range::in_range(0, 100));
  if (auto set = node.optional_child("set")) {
    for (const std::string& key : set->keys()) {
      set->mark_read(key);
      s.set.push_back({key, YAML::Dump(set->yaml()[key])});
    }
    // (`shellflow study` checks the case with them before the first run.)
  }
  node.finish();
  if (!c.coupling)
    throw_at(s.where, "a study runs a coupled case: the case needs a 'coupling' section (panel flutter)");
  if (s.parameter != StudySection::Parameter::thickness && !c.fluid)
    throw_at(s.where, fmt::format("parameter '{}' is a free-stream quantity; the case needs a 'fluid' section",
                                  to_string(s.parameter)));
  return s;
}

}  // namespace detail
}  // namespace shellflow::io
