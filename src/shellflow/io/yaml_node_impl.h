#pragma once
// Internal to the YAML reader (yaml_reader.cpp, yaml_reader_load.cpp): the document a node
// came from and YamlNode's state, shared by the loading and the reading of values.
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

// GCC 12 at -O2/-O3 reports false -Wdangling-pointer warnings inside yaml-cpp 0.7's inline
// Node accessors (InvalidNode(m_invalidKey)); they are not ours to fix.
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ >= 12
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdangling-pointer"
#endif
#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ >= 12
#pragma GCC diagnostic pop
#endif

#include "shellflow/core/error.h"
#include "shellflow/io/yaml_reader.h"

namespace shellflow::io {

namespace detail {

struct Document {
  std::string file;
  std::filesystem::path base_dir;
};

inline std::string describe_value(const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return "an empty value";
  if (node.IsMap()) return "a map";
  if (node.IsSequence()) return node.size() == 0 ? "an empty list" : "a list";
  const std::string& text = node.Scalar();
  return text.size() <= 60 ? fmt::format("'{}'", text)
                           : fmt::format("'{}...' ({} characters)", text.substr(0, 60), text.size());
}

inline int line_of(const YAML::Mark& mark, int fallback) {
  return mark.is_null() || mark.line < 0 ? fallback : mark.line + 1;
}

}  // namespace detail

struct YamlNode::Impl {
  struct Entry {
    std::string key;
    int line = 0;
    YAML::Node value;
    bool read = false;
    std::shared_ptr<Impl> child;  ///< set once the value was opened as a map or a list
  };

  std::shared_ptr<const detail::Document> doc;
  YAML::Node node;
  std::string path;
  int line = 1;
  std::vector<Entry> entries;                ///< for a map, in document order
  std::vector<std::shared_ptr<Impl>> items;  ///< for a list, once opened
  std::vector<std::string> known;            ///< keys the reader asked for, in order

  SourceLocation where() const { return {doc->file, line, path}; }
  std::string path_of(std::string_view key) const {
    return path.empty() ? std::string(key) : fmt::format("{}.{}", path, key);
  }
  [[noreturn]] void fail(std::string_view what) const { throw_at(where(), what); }

  Entry* find(std::string_view key) {
    for (auto& e : entries) {
      if (e.key == key) return &e;
    }
    return nullptr;
  }
  void add_known(std::string_view key) {
    if (std::find(known.begin(), known.end(), key) == known.end()) known.emplace_back(key);
  }

  static std::shared_ptr<Impl> make(std::shared_ptr<const detail::Document> doc, YAML::Node node, std::string path,
                                    int line) {
    auto impl = std::make_shared<Impl>();
    impl->doc = std::move(doc);
    impl->node = std::move(node);
    impl->path = std::move(path);
    impl->line = line;
    if (impl->node.IsMap()) impl->index_entries();
    return impl;
  }

  void index_entries() {
    for (auto it = node.begin(); it != node.end(); ++it) {
      // By value: `it->first` lives in a proxy that dies at the end of the statement.
      const YAML::Node key = it->first;
      const YAML::Node value = it->second;
      const int key_line = detail::line_of(key.Mark(), line);
      if (!key.IsScalar()) {
        throw_at({doc->file, key_line, path}, "expected a plain key name, got " + detail::describe_value(key));
      }
      if (const Entry* first = find(key.Scalar())) {
        throw_at({doc->file, key_line, path_of(key.Scalar())},
                 fmt::format("duplicate key; it was first given at line {}", first->line));
      }
      entries.push_back({key.Scalar(), key_line, value, false, nullptr});
    }
  }

  /// Appends the messages of the keys not read, in this map and the maps and lists below it
  /// (yaml_reader.cpp).
  void collect_unread(std::vector<std::pair<int, std::string>>& out) const;
};

}  // namespace shellflow::io
