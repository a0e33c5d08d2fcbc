// Loading a case file into a YamlNode: the one YAML document of the file or string, its
// syntax errors with a hint, and the `--set KEY=VALUE` overrides.
#include <fmt/format.h>

#include <cctype>
#include <fstream>
#include <optional>
#include <sstream>
#include <system_error>
#include <utility>

#include "shellflow/core/error.h"
#include "shellflow/io/yaml_node_impl.h"
#include "shellflow/io/yaml_reader.h"

namespace shellflow::io {

namespace fs = std::filesystem;

namespace {

using detail::describe_value;
using detail::Document;
using detail::line_of;

/// Records where each document of a stream starts (the mark of its first event).
class DocumentCounter : public YAML::EventHandler {
 public:
  std::optional<YAML::Mark> first_mark;  ///< of the current document's first node
  void OnDocumentStart(const YAML::Mark&) override { first_mark.reset(); }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& m, YAML::anchor_t) override { note(m); }
  void OnAlias(const YAML::Mark& m, YAML::anchor_t) override { note(m); }
  void OnScalar(const YAML::Mark& m, const std::string&, YAML::anchor_t, const std::string&) override { note(m); }
  void OnSequenceStart(const YAML::Mark& m, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    note(m);
  }
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark& m, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    note(m);
  }
  void OnMapEnd() override {}

 private:
  void note(const YAML::Mark& m) {
    if (!first_mark) first_mark = m;
  }
};

/// What to do about a YAML syntax error at 1-based `line` of `text` (0: unknown).
std::string syntax_hint(std::string_view text, int line) {
  std::size_t start = 0;
  for (int l = 1; l < line && start != std::string_view::npos; ++l) {
    start = text.find('\n', start);
    if (start != std::string_view::npos) ++start;
  }
  if (line > 0 && start != std::string_view::npos) {
    const std::string_view rest = text.substr(start);
    const std::string_view indent = rest.substr(0, rest.find_first_not_of(" \t"));
    if (indent.find('\t') != std::string_view::npos) return "indent with spaces: YAML does not allow tabs there";
  }
  return "check the brackets, quotes, ':' and indentation of this line and the one before it";
}

/// Number of documents in `text` and the 1-based line of the second one's first node.
/// A document that starts where the previous one started (the parser makes no progress, as
/// yaml-cpp 0.7 does on a lone ',') is a syntax error at that character.
std::pair<int, int> count_documents(const std::string& text) {
  std::istringstream in(text);
  YAML::Parser parser(in);
  DocumentCounter counter;
  int count = 0, second_line = 0;
  std::optional<int> previous_pos;
  while (parser.HandleNextDocument(counter)) {
    const YAML::Mark mark = counter.first_mark.value_or(YAML::Mark::null_mark());
    const int pos = mark.is_null() ? -1 : mark.pos;
    if (previous_pos && pos <= *previous_pos) {
      std::size_t at = pos >= 0 ? static_cast<std::size_t>(pos) : 0;
      while (at < text.size() && std::isspace(static_cast<unsigned char>(text[at]))) ++at;
      const auto byte = at < text.size() ? static_cast<unsigned char>(text[at]) : 0;
      const std::string what = at >= text.size()             ? std::string("unexpected text")
                               : byte >= 0x20 && byte < 0x7f ? fmt::format("unexpected '{}'", text[at])
                                                             : fmt::format("unexpected byte \\x{:02x}", byte);
      throw YAML::ParserException(mark, what);
    }
    previous_pos = pos;
    ++count;
    if (count == 2) second_line = line_of(mark, 1);
  }
  return {count, second_line};
}

}  // namespace

// ---- loading ----------------------------------------------------------------------------------

KeyOverride KeyOverride::parse(std::string_view text, std::string_view option) {
  const auto eq = text.find('=');
  if (eq == std::string_view::npos || eq == 0)
    throw InputError(
        fmt::format("{} '{}': expected KEY=VALUE, e.g. {} fluid.free_stream.mach=2.1", option, text, option));
  return {std::string(text.substr(0, eq)), std::string(text.substr(eq + 1))};
}

namespace {

/// Applies the overrides to the document's root map.
void apply_overrides(YAML::Node root, std::span<const KeyOverride> overrides, const std::string& file) {
  for (const KeyOverride& o : overrides) {
    std::vector<std::string> keys;
    for (std::size_t start = 0;;) {
      const auto dot = o.path.find('.', start);
      keys.push_back(o.path.substr(start, dot == std::string::npos ? std::string::npos : dot - start));
      if (dot == std::string::npos) break;
      start = dot + 1;
    }
    const std::string path = printable(o.path);
    for (const auto& k : keys)
      if (k.empty())
        throw InputError(
            fmt::format("{}: --set {}: empty key in the path; write keys like fluid.free_stream.mach", file, path));
    YAML::Node value;
    try {
      if (count_documents(o.value).first > 1)
        throw InputError(
            fmt::format("{}: --set {}={}: the value holds more than one YAML document; give one value "
                        "(no '---' separators)",
                        file, path, printable(o.value)));
      value = YAML::Load(o.value);
    } catch (const YAML::Exception& e) {
      throw InputError(
          fmt::format("{}: --set {}={}: the value is not valid YAML ({})", file, path, printable(o.value), e.msg));
    }
    YAML::Node node = root;
    std::string walked;
    for (std::size_t i = 0; i + 1 < keys.size(); ++i) {
      walked += (walked.empty() ? "" : ".") + keys[i];
      YAML::Node next = node[keys[i]];
      if (!next.IsDefined() || next.IsNull()) {
        node[keys[i]] = YAML::Node(YAML::NodeType::Map);
        next = node[keys[i]];
      } else if (!next.IsMap()) {
        throw InputError(
            fmt::format("{}: --set {}: '{}' is not a map of keys in the case file", file, path, printable(walked)));
      }
      node.reset(next);
    }
    node[keys.back()] = value;
  }
}

}  // namespace

YamlNode YamlNode::load_string(std::string_view text, const fs::path& file, std::span<const KeyOverride> overrides) {
  auto doc = std::make_shared<Document>();
  doc->file = file.string();
  doc->base_dir = file.parent_path();
  // yaml-cpp 0.7's LoadAll loops forever on some malformed streams (a lone ','): count the
  // documents with the event parser, stopping when a document starts where the previous one
  // did, then build the first document alone with Load.
  const std::string owned(text);
  YAML::Node root;
  try {
    const auto [count, second_line] = count_documents(owned);
    if (count > 1) {
      throw_at({doc->file, second_line, {}},
               fmt::format("expected one YAML document, found {}; remove the '---' separators", count));
    }
    root = YAML::Load(owned);
  } catch (const YAML::Exception& e) {
    const int line = line_of(e.mark, 0);
    throw_at({doc->file, line, {}}, fmt::format("YAML syntax error: {}; {}", e.msg, syntax_hint(owned, line)));
  }
  if (!root.IsMap()) {
    throw_at({doc->file, 1, {}}, fmt::format("expected a map of keys at the top level, got {}",
                                             root.IsNull() ? std::string("an empty document") : describe_value(root)));
  }
  apply_overrides(root, overrides, doc->file);
  return YamlNode(Impl::make(std::move(doc), root, {}, 1));
}

YamlNode YamlNode::load_file(const fs::path& file, std::span<const KeyOverride> overrides) {
  std::error_code ec;
  if (fs::is_directory(file, ec)) {
    throw InputError(fmt::format("{}: cannot open case file (it is a directory)", file.string()));
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    const char* reason = fs::exists(file, ec) ? "permission denied" : "no such file";
    throw InputError(fmt::format("{}: cannot open case file ({})", file.string(), reason));
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) {
    throw InputError(fmt::format("{}: cannot open case file (read error)", file.string()));
  }
  return load_string(text.str(), file, overrides);
}

}  // namespace shellflow::io
