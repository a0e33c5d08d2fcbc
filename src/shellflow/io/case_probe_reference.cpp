// A probe's reference curve (`probes[i].reference`, docs/case-format.md "Probes"): a column
// of a CSV file drawn beside the probe in probes.png. Checked when the case is read, so that
// `check` refuses a missing file, an unknown column or a row that is not numbers.
#include <fmt/format.h>

#include <charconv>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "shellflow/core/error.h"
#include "shellflow/io/case_sections.h"

namespace shellflow::io::detail {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

std::vector<std::string> split(std::string_view line) {
  std::vector<std::string> fields;
  for (std::size_t start = 0;;) {
    const std::size_t comma = line.find(',', start);
    fields.emplace_back(
        trim(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
    if (comma == std::string_view::npos) return fields;
    start = comma + 1;
  }
}

bool is_number(std::string_view s) {
  double value = 0.0;
  if (s.size() > 1 && s.front() == '+') s.remove_prefix(1);
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  return !s.empty() && ec == std::errc() && ptr == s.data() + s.size();
}

}  // namespace

Probe::Reference read_probe_reference(const YamlNode& node) {
  node.expect_map();
  Probe::Reference r;
  r.file = node.input_file("file");
  r.column = node.required<std::string>("column");
  r.scale = node.optional<double>("scale", 1.0, Range::any());
  if (!(r.scale != 0.0)) node.fail("scale", "must be a non-zero number, e.g. -1 to flip the sign");
  r.label = node.optional<std::string>("label", fmt::format("{}: {}", r.file.filename().string(), r.column));

  // CSV: lines starting with '#' are comments, the first other line is the header.
  std::ifstream in(r.file);
  if (!in) node.fail("file", fmt::format("cannot read '{}'", r.file.string()));
  std::vector<std::string> header;
  std::string line;
  int number = 0, rows = 0;
  while (std::getline(in, line)) {
    ++number;
    const std::string_view text = trim(line);
    if (text.empty() || text.front() == '#') continue;
    const std::vector<std::string> fields = split(text);
    if (header.empty()) {
      header = fields;
      continue;
    }
    if (fields.size() != header.size()) {
      node.fail("file", fmt::format("{}:{}: {} values, the header has {} columns; give every row all "
                                    "the columns",
                                    r.file.string(), number, fields.size(), header.size()));
    }
    for (const std::string& f : fields) {
      if (!is_number(f)) {
        node.fail("file", fmt::format("{}:{}: '{}' is not a number; the rows below the header hold "
                                      "numbers only",
                                      r.file.string(), number, f.substr(0, 40)));
      }
    }
    ++rows;
  }
  if (header.empty() || rows == 0) {
    node.fail("file", fmt::format("'{}' holds no {}; expected a header line (the abscissa first, e.g. "
                                  "load_factor,w_tip) and rows of numbers",
                                  r.file.string(), header.empty() ? "header" : "rows"));
  }
  const std::vector<std::string> columns(header.begin() + 1, header.end());
  bool found = false;
  for (const std::string& c : columns) found = found || c == r.column;
  if (!found) {
    std::string what = fmt::format("no column '{}' in {} (its first column, '{}', is the abscissa)", r.column,
                                   r.file.filename().string(), header.front());
    if (auto suggestion = closest_match(r.column, columns)) what += fmt::format("; did you mean '{}'?", *suggestion);
    what += fmt::format("; columns: {}", fmt::join(columns, ", "));
    node.fail("column", what);
  }
  node.finish();
  return r;
}

}  // namespace shellflow::io::detail
