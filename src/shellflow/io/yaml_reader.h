#pragma once
// A small reader on top of yaml-cpp that every section of a case file goes through, so that
// every module reads its keys the same way and reports bad input the same way:
//
//   FILE:LINE: KEY.PATH: what is wrong; what is expected
//   cases/panel.yaml:14: shell.thickness: must be > 0 m, got -0.001
//   cases/panel.yaml:9: meshes.fluid.ordr: unknown key; did you mean 'order'?
//
// Usage: open the file, take sections with child()/list(), read keys with required()/
// optional()/choice()/vec3()/input_file(), then call finish() on the section, which reports
// the first key that was never read as unknown (with a "did you mean" suggestion drawn from
// the keys the reader asked for).
//
//   YamlNode root = YamlNode::load_file("cases/panel.yaml");
//   YamlNode shell = root.child("shell");
//   double h = shell.required<double>("thickness", Range::positive(), "m");
//   shell.finish();
//
// A YamlNode is a cheap handle: copies share the record of which keys were read. Every error
// is thrown as shellflow::InputError with a one-line message.
#include <concepts>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "shellflow/core/types.h"

namespace YAML {
class Node;
}

namespace shellflow::io {

/// Where a value came from: `file:line: key.path`. Kept by the structs read from a case file
/// so that later checks (a physical group missing from a mesh) can point back to the line.
struct SourceLocation {
  std::string file;      ///< the file as the user named it (not made absolute)
  int line = 0;          ///< 1-based; 0 when unknown
  std::string key_path;  ///< dotted key path, e.g. `shell.supports[1].group`; empty for the root

  /// `file:line: key.path` (parts that are unknown are left out), the prefix of a message.
  std::string prefix() const;
  /// `prefix(): message` — the one-line error text.
  std::string message(std::string_view what) const;
};

/// Throws InputError with `where.message(what)`.
[[noreturn]] void throw_at(const SourceLocation& where, std::string_view what);

/// An allowed interval for a number; printed in messages as "> 0", ">= 1", "in (-1, 0.5)".
struct Range {
  std::optional<double> lo, hi;
  bool lo_open = false;  ///< true: lo excluded
  bool hi_open = false;  ///< true: hi excluded

  static Range any() { return {}; }
  static Range positive() { return {0.0, std::nullopt, true, false}; }            ///< x > 0
  static Range non_negative() { return {0.0, std::nullopt, false, false}; }       ///< x >= 0
  static Range greater_than(double a) { return {a, std::nullopt, true, false}; }  ///< x > a
  static Range at_least(double a) { return {a, std::nullopt, false, false}; }     ///< x >= a
  static Range in_range(double a, double b) { return {a, b, false, false}; }      ///< a <= x <= b
  static Range open(double a, double b) { return {a, b, true, true}; }            ///< a < x < b

  bool contains(double x) const;
  /// "> 0 m", ">= 1", "in (-1, 0.5)", "in [0, 1] m"; empty for any().
  std::string describe(std::string_view unit = {}) const;
};

/// Edit distance (optimal string alignment: insertions, deletions, substitutions and swaps
/// of neighbours), used for "did you mean" suggestions.
std::size_t edit_distance(std::string_view a, std::string_view b);
/// The candidate closest to `word` if it is close enough to be a likely misspelling.
std::optional<std::string> closest_match(std::string_view word, const std::vector<std::string>& candidates);

/// A command-line replacement of one key of a case file (`shellflow run --set KEY=VALUE`):
/// `path` is dotted through maps (`fluid.free_stream.mach`), `value` is YAML (`2.1`,
/// `piston_theory`, `[0.02, 0.06]`). Missing maps along the path are created, so a misspelt
/// key is reported as unknown by the section's reader, like one in the file.
struct KeyOverride {
  std::string path;
  std::string value;
  /// Parses `KEY=VALUE`; throws InputError naming `option` when there is no `=` or no key.
  static KeyOverride parse(std::string_view text, std::string_view option = "--set");
};

/// One node of a YAML document (a map, a list, or a scalar) with the file it came from, the
/// line it was referenced at and its dotted key path.
class YamlNode {
 public:
  /// Reads and parses a file. Throws InputError: `FILE: cannot open case file (...)`,
  /// `FILE:LINE: YAML syntax error: ...`, or `FILE:1: expected a map of keys ...`; and for
  /// an override whose path runs through a key that is not a map.
  static YamlNode load_file(const std::filesystem::path& file, std::span<const KeyOverride> overrides = {});
  /// Parses text; `file` is used in messages and to resolve relative paths.
  static YamlNode load_string(std::string_view text, const std::filesystem::path& file,
                              std::span<const KeyOverride> overrides = {});

  YamlNode();  ///< an empty handle; only useful as a placeholder
  ~YamlNode();
  YamlNode(const YamlNode&);
  YamlNode& operator=(const YamlNode&);
  YamlNode(YamlNode&&) noexcept;
  YamlNode& operator=(YamlNode&&) noexcept;

  // ---- where this node is -------------------------------------------------------------------
  const std::string& file() const;         ///< the file as named by the user
  std::filesystem::path base_dir() const;  ///< directory of the file (for relative paths)
  int line() const;                        ///< 1-based line where this node is referenced
  const std::string& key_path() const;     ///< e.g. `shell.supports[1]`; empty for the root
  SourceLocation location() const;
  /// Location of `key` of this map (its line if present, this node's line otherwise).
  SourceLocation location(std::string_view key) const;
  /// Key path of `key` below this node: `shell` + `thickness` -> `shell.thickness`.
  std::string path_of(std::string_view key) const;

  bool is_scalar() const;
  bool is_null() const;
  /// The underlying yaml-cpp node (escape hatch; reading through it does not mark keys read).
  const YAML::Node& yaml() const;

  // ---- keys of a map --------------------------------------------------------------------------
  /// True if this map has `key`. Records `key` as known (for suggestions); does not read it.
  bool has(std::string_view key) const;
  /// Number of entries of a map, or items of a list.
  std::size_t size() const;
  /// Keys of this map in document order.
  std::vector<std::string> keys() const;

  /// Required scalar: T is bool, std::string, or an arithmetic type (integers are checked to
  /// be whole and to fit T). Errors: missing key, wrong type ("expected a number, got 'abc'").
  template <class T>
  T required(std::string_view key) const;
  /// Optional scalar: `fallback` when the key is absent.
  template <class T>
  T optional(std::string_view key, T fallback) const;
  /// Optional scalar without a default.
  template <class T>
  std::optional<T> maybe(std::string_view key) const;

  /// Numbers with a range check: "must be > 0 m, got -0.001". `unit` is printed after the
  /// bound ("m", "Pa", "kg/m^3"; empty for dimensionless).
  template <class T>
  requires std::is_arithmetic_v<T> T required(std::string_view key, const Range& range, std::string_view unit = {})
  const;
  template <class T>
  requires std::is_arithmetic_v<T> T optional(std::string_view key, T fallback, const Range& range,
                                              std::string_view unit = {})
  const;

  /// Enumerations: the value must be one of `allowed` ("unknown value 'clampd'; did you mean
  /// 'clamped'? (one of: clamped, ...)").
  std::string choice(std::string_view key, std::initializer_list<std::string_view> allowed) const;
  std::string choice(std::string_view key, std::initializer_list<std::string_view> allowed,
                     std::string_view fallback) const;
  std::string choice(std::string_view key, std::span<const std::string_view> allowed) const;
  std::string choice(std::string_view key, std::span<const std::string_view> allowed, std::string_view fallback) const;
  /// An enumeration read by name: `names[i]` is the name of `static_cast<E>(i)`.
  template <class E>
  requires std::is_enum_v<E> E enumeration(std::string_view key, std::span<const std::string_view> names)
  const;
  template <class E>
  requires std::is_enum_v<E> E enumeration(std::string_view key, std::span<const std::string_view> names, E fallback)
  const;

  /// A list of exactly three numbers `[x, y, z]`.
  Vec3 vec3(std::string_view key) const;
  Vec3 vec3(std::string_view key, const Vec3& fallback) const;

  /// A file path relative to the directory of the case file (absolute paths are kept). With
  /// `must_exist` it must name an existing regular file ("file not found: ...").
  /// Returns the resolved path (case directory / value, lexically normalised).
  std::filesystem::path input_file(std::string_view key, bool must_exist = true) const;

  /// A map below this map. A missing key is an error; an empty value (`key:`) is an empty map.
  YamlNode child(std::string_view key) const;
  /// A map below this map, or nullopt if the key is absent.
  std::optional<YamlNode> optional_child(std::string_view key) const;
  /// The items of a list below this map (paths `key[0]`, `key[1]`, ...). A missing key is an
  /// error; an empty value is an empty list.
  std::vector<YamlNode> list(std::string_view key) const;
  /// Like list(), but an absent key gives an empty list.
  std::vector<YamlNode> optional_list(std::string_view key) const;

  /// Marks `key` as read without reading it (a key kept for compatibility, or read through
  /// yaml()).
  void mark_read(std::string_view key) const;

  // ---- this node as a value -------------------------------------------------------------------
  /// Checks this node is a map (an empty value counts as an empty map); "expected a map ...".
  void expect_map() const;
  /// This node as a scalar of type T (used for list items).
  template <class T>
  T as() const;

  // ---- errors -----------------------------------------------------------------------------------
  /// Throws InputError at this node: `FILE:LINE: key.path: what`.
  [[noreturn]] void fail(std::string_view what) const;
  /// Throws InputError at `key` of this map: `FILE:LINE: key.path.key: what`.
  [[noreturn]] void fail(std::string_view key, std::string_view what) const;
  /// "missing required key 'x'" at this map — or, when an unread key looks like a misspelling
  /// of one of `keys`, "unknown key; did you mean ..." at that key's line. `what` replaces the
  /// default "missing required key 'x'" text when given.
  [[noreturn]] void fail_missing(std::initializer_list<std::string_view> keys, std::string_view what = {}) const;

  /// Throws InputError for the first key (in document order) of this node and of every node
  /// taken from it that was never read: `unknown key; did you mean 'X'?` or
  /// `unknown key; expected one of: a, b, c`. Does nothing when every key was read.
  void finish() const;
  /// The messages finish() would report, one per unread key, in document order.
  std::vector<std::string> unread_keys() const;

 private:
  struct Impl;
  explicit YamlNode(std::shared_ptr<Impl> impl);

  // Conversions behind the templates (defined in yaml_reader.cpp). `key` empty: this node.
  double read_double(std::string_view key) const;
  std::int64_t read_integer(std::string_view key, std::int64_t lo, std::int64_t hi) const;
  bool read_bool(std::string_view key) const;
  std::string read_string(std::string_view key) const;
  void check_range(std::string_view key, double value, const Range& range, std::string_view unit) const;
  // Registers `key` as known; true if present (and then marks it read when `consume`).
  bool lookup(std::string_view key, bool consume) const;
  [[noreturn]] void fail_missing_key(std::string_view key) const;

  template <class T>
  T read_value(std::string_view key) const;

  std::shared_ptr<Impl> impl_;
};

// ---- template definitions ---------------------------------------------------------------------

template <class T>
T YamlNode::read_value(std::string_view key) const {
  if constexpr (std::is_same_v<T, bool>) {
    return read_bool(key);
  } else if constexpr (std::is_same_v<T, std::string>) {
    return read_string(key);
  } else if constexpr (std::is_integral_v<T>) {
    constexpr std::int64_t lo = std::is_signed_v<T> ? static_cast<std::int64_t>(std::numeric_limits<T>::lowest()) : 0;
    constexpr std::int64_t hi = std::is_unsigned_v<T> && sizeof(T) >= sizeof(std::int64_t)
                                    ? std::numeric_limits<std::int64_t>::max()
                                    : static_cast<std::int64_t>(std::numeric_limits<T>::max());
    return static_cast<T>(read_integer(key, lo, hi));
  } else if constexpr (std::is_floating_point_v<T>) {
    return static_cast<T>(read_double(key));
  } else {
    static_assert(std::is_same_v<T, bool>, "YamlNode reads bool, std::string and numbers");
  }
}

template <class T>
T YamlNode::required(std::string_view key) const {
  if (!lookup(key, true)) fail_missing_key(key);
  return read_value<T>(key);
}

template <class T>
T YamlNode::optional(std::string_view key, T fallback) const {
  if (!lookup(key, true)) return fallback;
  return read_value<T>(key);
}

template <class T>
std::optional<T> YamlNode::maybe(std::string_view key) const {
  if (!lookup(key, true)) return std::nullopt;
  return read_value<T>(key);
}

template <class T>
requires std::is_arithmetic_v<T> T YamlNode::required(std::string_view key, const Range& range, std::string_view unit)
const {
  const T value = required<T>(key);
  check_range(key, static_cast<double>(value), range, unit);
  return value;
}

template <class T>
requires std::is_arithmetic_v<T> T YamlNode::optional(std::string_view key, T fallback, const Range& range,
                                                      std::string_view unit)
const {
  if (!lookup(key, true)) return fallback;
  const T value = read_value<T>(key);
  check_range(key, static_cast<double>(value), range, unit);
  return value;
}

template <class E>
requires std::is_enum_v<E> E YamlNode::enumeration(std::string_view key, std::span<const std::string_view> names)
const {
  const std::string value = choice(key, names);
  std::size_t i = 0;
  while (names[i] != value) ++i;
  return static_cast<E>(i);
}

template <class E>
requires std::is_enum_v<E> E YamlNode::enumeration(std::string_view key, std::span<const std::string_view> names,
                                                   E fallback)
const {
  if (!has(key)) return fallback;
  return enumeration<E>(key, names);
}

template <class T>
T YamlNode::as() const {
  return read_value<T>({});
}

}  // namespace shellflow::io
