// The YAML reader: messages (SourceLocation, Range, suggestions) and the reading of keys,
// values, children and unread keys; loading a document is in yaml_reader_load.cpp.
#include "shellflow/io/yaml_reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <system_error>
#include <utility>

#include "shellflow/core/error.h"
#include "shellflow/io/yaml_node_impl.h"

namespace shellflow::io {

namespace fs = std::filesystem;

// ---- SourceLocation, Range, suggestions ---------------------------------------------------------

std::string SourceLocation::prefix() const {
  std::string s = file;
  if (line > 0) s += fmt::format(":{}", line);
  if (!key_path.empty()) s += ": " + key_path;
  return s;
}

std::string SourceLocation::message(std::string_view what) const {
  // One line, nothing for the terminal to interpret: keys and values quoted from the file
  // may hold any byte.
  return printable(fmt::format("{}: {}", prefix(), what));
}

void throw_at(const SourceLocation& where, std::string_view what) { throw InputError(where.message(what)); }

bool Range::contains(double x) const {
  if (std::isnan(x)) return false;
  if (lo && (lo_open ? !(x > *lo) : !(x >= *lo))) return false;
  if (hi && (hi_open ? !(x < *hi) : !(x <= *hi))) return false;
  return true;
}

std::string Range::describe(std::string_view unit) const {
  std::string s;
  if (lo && hi) {
    s = fmt::format("in {}{}, {}{}", lo_open ? '(' : '[', *lo, *hi, hi_open ? ')' : ']');
  } else if (lo) {
    s = fmt::format("{} {}", lo_open ? ">" : ">=", *lo);
  } else if (hi) {
    s = fmt::format("{} {}", hi_open ? "<" : "<=", *hi);
  }
  if (!s.empty() && !unit.empty()) s += fmt::format(" {}", unit);
  return s;
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
  // Optimal string alignment distance, full table (keys are short).
  const std::size_t n = a.size();
  const std::size_t m = b.size();
  std::vector<std::size_t> d((n + 1) * (m + 1));
  auto at = [m, &d](std::size_t i, std::size_t j) -> std::size_t& { return d[i * (m + 1) + j]; };
  for (std::size_t i = 0; i <= n; ++i) at(i, 0) = i;
  for (std::size_t j = 0; j <= m; ++j) at(0, j) = j;
  for (std::size_t i = 1; i <= n; ++i) {
    for (std::size_t j = 1; j <= m; ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      at(i, j) = std::min({at(i - 1, j) + 1, at(i, j - 1) + 1, at(i - 1, j - 1) + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
        at(i, j) = std::min(at(i, j), at(i - 2, j - 2) + 1);
      }
    }
  }
  return at(n, m);
}

namespace {

std::string lowercase(std::string_view s) {
  std::string out(s);
  for (char& c : out) {
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (c == '-' || c == ' ') c = '_';
  }
  return out;
}

std::string join(const std::vector<std::string>& items, std::string_view sep) {
  return fmt::format("{}", fmt::join(items, sep));
}

}  // namespace

std::optional<std::string> closest_match(std::string_view word, const std::vector<std::string>& candidates) {
  const std::string w = lowercase(word);
  std::optional<std::string> best;
  std::size_t best_distance = std::numeric_limits<std::size_t>::max();
  for (const auto& candidate : candidates) {
    if (candidate == word) continue;
    const std::string c = lowercase(candidate);
    std::size_t d = edit_distance(w, c);
    const std::size_t longest = std::max(w.size(), c.size());
    const std::size_t allowed = std::clamp<std::size_t>(longest / 3, 1, 3);
    // A prefix of at least 4 characters ("poisson" for "poisson_ratio") is also a match.
    const bool prefix = std::min(w.size(), c.size()) >= 4 && (c.starts_with(w) || w.starts_with(c));
    // A word must keep some of its letters to be a misspelling ("w" is no misspelling of "x").
    const bool close = d <= allowed && d < std::min(w.size(), c.size());
    if (!close && !prefix) continue;
    if (d > allowed) d = allowed + 1;  // rank prefix matches after close misspellings
    if (d < best_distance) {
      best_distance = d;
      best = candidate;
    }
  }
  return best;
}

// ---- YamlNode internals (yaml_node_impl.h) ----------------------------------------------------

namespace {

using detail::describe_value;
using detail::line_of;

}  // namespace

void YamlNode::Impl::collect_unread(std::vector<std::pair<int, std::string>>& out) const {
  for (const auto& e : entries) {
    if (!e.read) {
      std::string what;
      if (std::find(known.begin(), known.end(), e.key) != known.end()) {
        what = "key not allowed here";
      } else if (auto suggestion = closest_match(e.key, known)) {
        what = fmt::format("unknown key; did you mean '{}'?", *suggestion);
      } else if (!known.empty()) {
        what = fmt::format("unknown key; expected one of: {}", join(known, ", "));
      } else {
        what = "unknown key; this section takes no keys";
      }
      out.emplace_back(e.line, SourceLocation{doc->file, e.line, path_of(e.key)}.message(what));
    } else if (e.child) {
      e.child->collect_unread(out);
    }
  }
  for (const auto& item : items) item->collect_unread(out);
}

YamlNode::YamlNode() = default;
YamlNode::~YamlNode() = default;
YamlNode::YamlNode(const YamlNode&) = default;
YamlNode& YamlNode::operator=(const YamlNode&) = default;
YamlNode::YamlNode(YamlNode&&) noexcept = default;
YamlNode& YamlNode::operator=(YamlNode&&) noexcept = default;
YamlNode::YamlNode(std::shared_ptr<Impl> impl) : impl_(std::move(impl)) {}

// ---- location -----------------------------------------------------------------------------------

const std::string& YamlNode::file() const { return impl_->doc->file; }
fs::path YamlNode::base_dir() const { return impl_->doc->base_dir; }
int YamlNode::line() const { return impl_->line; }
const std::string& YamlNode::key_path() const { return impl_->path; }
SourceLocation YamlNode::location() const { return impl_->where(); }

SourceLocation YamlNode::location(std::string_view key) const {
  const Impl::Entry* e = impl_->find(key);
  return {impl_->doc->file, e ? e->line : impl_->line, impl_->path_of(key)};
}

std::string YamlNode::path_of(std::string_view key) const { return impl_->path_of(key); }

bool YamlNode::is_scalar() const { return impl_->node.IsScalar(); }
bool YamlNode::is_null() const { return impl_->node.IsNull(); }
const YAML::Node& YamlNode::yaml() const { return impl_->node; }

void YamlNode::fail(std::string_view what) const { impl_->fail(what); }

void YamlNode::fail(std::string_view key, std::string_view what) const { throw_at(location(key), what); }

// ---- keys ---------------------------------------------------------------------------------------

void YamlNode::expect_map() const {
  if (!impl_->node.IsMap() && !impl_->node.IsNull()) {
    impl_->fail("expected a map of keys, got " + describe_value(impl_->node));
  }
}

bool YamlNode::lookup(std::string_view key, bool consume) const {
  expect_map();
  impl_->add_known(key);
  Impl::Entry* e = impl_->find(key);
  if (e && consume) e->read = true;
  return e != nullptr;
}

bool YamlNode::has(std::string_view key) const { return lookup(key, false); }

void YamlNode::mark_read(std::string_view key) const { lookup(key, true); }

std::size_t YamlNode::size() const {
  if (impl_->node.IsMap()) return impl_->entries.size();
  if (impl_->node.IsSequence()) return impl_->node.size();
  return 0;
}

std::vector<std::string> YamlNode::keys() const {
  std::vector<std::string> out;
  for (const auto& e : impl_->entries) out.push_back(e.key);
  return out;
}

void YamlNode::fail_missing(std::initializer_list<std::string_view> keys, std::string_view what) const {
  // A key that is present but was never read and looks like one of the missing ones is most
  // likely a misspelling of it: report it where it is.
  std::vector<std::string> wanted(keys.begin(), keys.end());
  for (const auto& e : impl_->entries) {
    if (e.read) continue;
    if (std::find(impl_->known.begin(), impl_->known.end(), e.key) != impl_->known.end()) continue;
    if (auto suggestion = closest_match(e.key, wanted)) {
      throw_at({impl_->doc->file, e.line, impl_->path_of(e.key)},
               fmt::format("unknown key; did you mean '{}'?", *suggestion));
    }
  }
  if (!what.empty()) impl_->fail(what);
  std::string names;
  for (std::size_t i = 0; i < wanted.size(); ++i) {
    if (i > 0) names += i + 1 == wanted.size() ? " or " : ", ";
    names += "'" + wanted[i] + "'";
  }
  impl_->fail(fmt::format("missing required key {}", names));
}

void YamlNode::fail_missing_key(std::string_view key) const { fail_missing({key}); }

// ---- scalars ------------------------------------------------------------------------------------

namespace {

struct Value {
  YAML::Node node;
  SourceLocation where;
};

// The node behind `key` (or this node for an empty key) with its location, for conversions.
Value value_of(const YamlNode& self, std::string_view key) {
  if (key.empty()) return {self.yaml(), self.location()};
  return {self.yaml()[std::string(key)], self.location(key)};
}

const std::string& scalar_text(const Value& v, std::string_view expected) {
  if (!v.node.IsScalar()) {
    throw_at(v.where, fmt::format("expected {}, got {}", expected, describe_value(v.node)));
  }
  return v.node.Scalar();
}

std::string_view strip_plus(std::string_view s) {
  if (s.size() > 1 && s.front() == '+') s.remove_prefix(1);
  return s;
}

}  // namespace

double YamlNode::read_double(std::string_view key) const {
  const Value v = value_of(*this, key);
  const std::string& text = scalar_text(v, "a number");
  const std::string_view s = strip_plus(text);
  double x = 0.0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), x);
  if (ec == std::errc::result_out_of_range) {
    throw_at(v.where, fmt::format("number out of range, got '{}'", text));
  }
  if (ec != std::errc() || ptr != s.data() + s.size() || !std::isfinite(x)) {
    throw_at(v.where, fmt::format("expected a number, got '{}'", text));
  }
  return x;
}

std::int64_t YamlNode::read_integer(std::string_view key, std::int64_t lo, std::int64_t hi) const {
  const Value v = value_of(*this, key);
  const std::string& text = scalar_text(v, "an integer");
  const std::string_view s = strip_plus(text);
  std::int64_t x = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), x);
  if (ec == std::errc::result_out_of_range || (ec == std::errc() && (x < lo || x > hi))) {
    throw_at(v.where, fmt::format("must be in [{}, {}], got '{}'", lo, hi, text));
  }
  if (ec != std::errc() || ptr != s.data() + s.size()) {
    throw_at(v.where, fmt::format("expected an integer, got '{}'", text));
  }
  return x;
}

bool YamlNode::read_bool(std::string_view key) const {
  const Value v = value_of(*this, key);
  const std::string t = lowercase(scalar_text(v, "true or false"));
  if (t == "true" || t == "yes" || t == "on") return true;
  if (t == "false" || t == "no" || t == "off") return false;
  throw_at(v.where, fmt::format("expected true or false, got '{}'", v.node.Scalar()));
}

std::string YamlNode::read_string(std::string_view key) const {
  const Value v = value_of(*this, key);
  return scalar_text(v, "a string");
}

void YamlNode::check_range(std::string_view key, double value, const Range& range, std::string_view unit) const {
  if (range.contains(value)) return;
  const Value v = value_of(*this, key);
  throw_at(v.where, fmt::format("must be {}, got {}", range.describe(unit), v.node.Scalar()));
}

std::string YamlNode::choice(std::string_view key, std::span<const std::string_view> allowed) const {
  const std::string value = required<std::string>(key);
  std::vector<std::string> names(allowed.begin(), allowed.end());
  if (std::find(names.begin(), names.end(), value) != names.end()) return value;
  std::string what = fmt::format("unknown value '{}'; ", value);
  if (auto suggestion = closest_match(value, names)) {
    what += fmt::format("did you mean '{}'? (one of: {})", *suggestion, join(names, ", "));
  } else {
    what += fmt::format("expected one of: {}", join(names, ", "));
  }
  fail(key, what);
}

std::string YamlNode::choice(std::string_view key, std::span<const std::string_view> allowed,
                             std::string_view fallback) const {
  if (!has(key)) return std::string(fallback);
  return choice(key, allowed);
}

std::string YamlNode::choice(std::string_view key, std::initializer_list<std::string_view> allowed) const {
  return choice(key, std::span<const std::string_view>(allowed.begin(), allowed.size()));
}

std::string YamlNode::choice(std::string_view key, std::initializer_list<std::string_view> allowed,
                             std::string_view fallback) const {
  return choice(key, std::span<const std::string_view>(allowed.begin(), allowed.size()), fallback);
}

Vec3 YamlNode::vec3(std::string_view key) const {
  if (!lookup(key, true)) fail_missing_key(key);
  const Value v = value_of(*this, key);
  if (!v.node.IsSequence() || v.node.size() != 3) {
    std::string got = describe_value(v.node);
    if (v.node.IsSequence()) got = fmt::format("a list of {} items", v.node.size());
    throw_at(v.where, "expected a list of 3 numbers [x, y, z], got " + got);
  }
  Vec3 out;
  for (int i = 0; i < 3; ++i) {
    const YAML::Node item = v.node[static_cast<std::size_t>(i)];
    const SourceLocation where{v.where.file, line_of(item.Mark(), v.where.line),
                               fmt::format("{}[{}]", v.where.key_path, i)};
    YamlNode item_node(Impl::make(impl_->doc, item, where.key_path, where.line));
    out[i] = item_node.as<double>();
  }
  return out;
}

Vec3 YamlNode::vec3(std::string_view key, const Vec3& fallback) const {
  if (!has(key)) return fallback;
  return vec3(key);
}

fs::path YamlNode::input_file(std::string_view key, bool must_exist) const {
  const std::string text = required<std::string>(key);
  if (text.empty()) fail(key, "expected a file name, got an empty string");
  fs::path p(text);
  if (p.is_relative()) p = impl_->doc->base_dir / p;
  p = p.lexically_normal();
  if (must_exist) {
    std::error_code ec;
    if (fs::is_directory(p, ec)) {
      fail(key, fmt::format("'{}' is a directory; expected a file", text));
    }
    if (!fs::is_regular_file(p, ec)) {
      fail(key, fmt::format("file not found: '{}' (looked for '{}'); paths are relative to the "
                            "case file's directory",
                            text, p.string()));
    }
  }
  return p;
}

// ---- children -----------------------------------------------------------------------------------

YamlNode YamlNode::child(std::string_view key) const {
  if (!lookup(key, true)) fail_missing_key(key);
  Impl::Entry& e = *impl_->find(key);
  if (!e.child) {
    if (!e.value.IsMap() && !e.value.IsNull()) {
      fail(key, "expected a map of keys, got " + describe_value(e.value));
    }
    e.child = Impl::make(impl_->doc, e.value, impl_->path_of(key), e.line);
  } else if (e.child->node.IsSequence()) {
    fail(key, "expected a map of keys, got a list");
  }
  return YamlNode(e.child);
}

std::optional<YamlNode> YamlNode::optional_child(std::string_view key) const {
  if (!has(key)) return std::nullopt;
  return child(key);
}

std::vector<YamlNode> YamlNode::list(std::string_view key) const {
  if (!lookup(key, true)) fail_missing_key(key);
  Impl::Entry& e = *impl_->find(key);
  if (!e.child) {
    if (!e.value.IsSequence() && !e.value.IsNull()) {
      fail(key, "expected a list, got " + describe_value(e.value));
    }
    auto seq = Impl::make(impl_->doc, e.value, impl_->path_of(key), e.line);
    if (e.value.IsSequence()) {
      for (std::size_t i = 0; i < e.value.size(); ++i) {
        const YAML::Node item = e.value[i];
        seq->items.push_back(
            Impl::make(impl_->doc, item, fmt::format("{}[{}]", seq->path, i), line_of(item.Mark(), e.line)));
      }
    }
    e.child = std::move(seq);
  } else if (e.child->node.IsMap()) {
    fail(key, "expected a list, got a map");
  }
  std::vector<YamlNode> out;
  for (const auto& item : e.child->items) out.push_back(YamlNode(item));
  return out;
}

std::vector<YamlNode> YamlNode::optional_list(std::string_view key) const {
  if (!has(key)) return {};
  return list(key);
}

// ---- unread keys --------------------------------------------------------------------------------

std::vector<std::string> YamlNode::unread_keys() const {
  std::vector<std::pair<int, std::string>> found;
  impl_->collect_unread(found);
  std::stable_sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::string> out;
  out.reserve(found.size());
  for (auto& f : found) out.push_back(std::move(f.second));
  return out;
}

void YamlNode::finish() const {
  const auto unread = unread_keys();
  if (unread.empty()) return;
  std::string message = unread.front();
  if (unread.size() > 1) {
    message += fmt::format(" (and {} more unknown key{})", unread.size() - 1, unread.size() > 2 ? "s" : "");
  }
  throw InputError(message);
}

}  // namespace shellflow::io
