// Fuzz target: the case-file reader, as `shellflow check` runs it up to (not including) the
// meshes: YAML text (+ --set overrides) -> io::Case, every key, type, range and file checked.
//
// Input: the case file's text. Leading lines `#set KEY=VALUE` (YAML comments, so the text
// stays a case file) are also applied as --set overrides, so that the override code is
// fuzzed too. Relative mesh paths resolve from cases/panel_flutter/, so that the seeds from
// cases/ reach past the file checks.
//
// A shellflow::Error is the expected answer to a bad input, and its message must be one line
// without control bytes (main() prints it to the terminal); any other exception (main()
// reports it as "internal error", exit 3), a crash, a hang or a sanitizer report is a finding.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_util.h"
#include "shellflow/core/error.h"
#include "shellflow/io/case.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace shellflow;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    std::vector<io::KeyOverride> overrides;
    std::size_t start = 0;
    while (overrides.size() < 4 && text.substr(start).starts_with("#set ")) {
      std::size_t end = text.find('\n', start);
      if (end == std::string_view::npos) end = text.size();
      overrides.push_back(io::KeyOverride::parse(text.substr(start + 5, end - start - 5)));
      start = end + (end < text.size() ? 1 : 0);
    }
    static const std::string file = SHELLFLOW_SOURCE_DIR "/cases/panel_flutter/fuzz.yaml";
    const io::Case c = io::read_case_string(text, file, overrides);
    (void)c;
  } catch (const Error& e) {
    // The reader's answer to a bad case file. (An override's text comes from the command
    // line, and its messages quote it as typed.)
    if (!text.starts_with("#set ")) fuzz::require_one_line(e.what());
  }
  return 0;
}
