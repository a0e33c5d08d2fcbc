#pragma once
// The two pieces of JSON text shellflow writes by hand (summaries: flutter.json, study.json,
// response.json, point.json): numbers, with null for what JSON cannot hold, and strings.
#include <fmt/format.h>

#include <cmath>
#include <string>
#include <string_view>

namespace shellflow {

/// A JSON number (10 significant digits); null when not finite (JSON has no NaN or infinity).
inline std::string json_number(double x) { return std::isfinite(x) ? fmt::format("{:.10g}", x) : "null"; }

/// A quoted JSON string: quotes and backslashes escaped, control characters as \u00XX.
inline std::string json_string(std::string_view s) {
  std::string out = "\"";
  for (const char ch : s) {
    if (ch == '"' || ch == '\\') {
      out += '\\';
      out += ch;
    } else if (static_cast<unsigned char>(ch) < 0x20) {
      out += fmt::format("\\u{:04x}", static_cast<unsigned>(static_cast<unsigned char>(ch)));
    } else {
      out += ch;
    }
  }
  return out + "\"";
}

}  // namespace shellflow
