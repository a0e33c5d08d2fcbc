#pragma once
// Shared by the fuzz targets.
#include <cstdio>
#include <cstdlib>

namespace shellflow::fuzz {

/// Aborts (a finding) unless `message` is one printable line: main() prints error messages
/// to the terminal, where a newline breaks the one-line rule and an escape byte is obeyed.
inline void require_one_line(const char* message) {
  for (const char* p = message; *p; ++p) {
    const auto b = static_cast<unsigned char>(*p);
    if (b < 0x20 || b == 0x7f) {
      std::fprintf(stderr, "fuzz: the error message holds byte 0x%02x: %s\n", b, message);
      std::abort();
    }
  }
}

}  // namespace shellflow::fuzz
