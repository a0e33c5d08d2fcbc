#pragma once
// Errors carry their full context (file, line, entity, fix) in the message, so that
// `main` can print them as one line. Library code throws; only `app/` catches.
#include <fmt/format.h>

#include <stdexcept>
#include <string>
#include <string_view>

namespace shellflow {

/// Any error shellflow reports to the user.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Bad input: a case file, a mesh file, a value out of range. The message starts with
/// `FILE:LINE:` when the location is known.
class InputError : public Error {
 public:
  using Error::Error;
};

/// A run that cannot go on: a diverging iteration, an inverted element, a negative density.
class SolverError : public Error {
 public:
  using Error::Error;
};

template <class... Args>
[[noreturn]] void throw_input_error(fmt::format_string<Args...> f, Args&&... args) {
  throw InputError(fmt::format(f, std::forward<Args>(args)...));
}

/// `text` with control bytes (newlines, escapes) and every byte >= 0x7f shown as \xNN:
/// quoted input in a one-line message, nothing for the terminal to interpret (bytes >= 0x80
/// may be C1 controls, or not text at all in a binary file given as a case).
inline std::string printable(std::string_view text) {
  std::string out;
  for (const char ch : text) {
    const auto b = static_cast<unsigned char>(ch);
    if (b < 0x20 || b >= 0x7f) {
      out += fmt::format("\\x{:02x}", b);
    } else {
      out += ch;
    }
  }
  return out;
}

}  // namespace shellflow
