// The `.msh` check of gmsh_input_check.h (format 4.1 ASCII: $MeshFormat, $PhysicalNames,
// $Entities, $Nodes, $Elements), run before Gmsh reads the file.
#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <unordered_set>
#include <utility>
#include <vector>

#include "shellflow/core/error.h"
#include "shellflow/mesh/gmsh_input_check.h"

namespace shellflow::mesh {
namespace fs = std::filesystem;

namespace {

/// Up to 40 bytes of a line for a message, bytes outside printable ASCII as \xNN (a binary
/// or damaged file must not put raw bytes on the terminal).
std::string excerpt(std::string_view s) {
  std::string out;
  for (const char ch : s.substr(0, 40)) {
    const auto b = static_cast<unsigned char>(ch);
    out += b >= 0x20 && b < 0x7f ? std::string(1, ch) : fmt::format("\\x{:02x}", b);
  }
  return out;
}

// ---- .msh files -----------------------------------------------------------------------------

struct MshLine {
  std::string_view text;
  int number;
};

std::vector<MshLine> split_lines(std::string_view s) {
  std::vector<MshLine> lines;
  std::size_t start = 0;
  int number = 1;
  while (start < s.size()) {
    std::size_t end = s.find('\n', start);
    if (end == std::string_view::npos) end = s.size();
    std::string_view line = s.substr(start, end - start);
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.remove_suffix(1);
    lines.push_back({line, number++});
    start = end + 1;
  }
  return lines;
}

constexpr std::string_view kMshFix = "re-export the mesh from Gmsh (format 4.1, ASCII)";

/// The tokens of one section, read one by one with the line each comes from.
class SectionReader {
 public:
  SectionReader(const fs::path& file, std::string section, const std::vector<MshLine>& lines, std::size_t begin,
                std::size_t end)
      : file_(file),
        section_(std::move(section)),
        lines_(lines),
        line_(begin),
        end_(end),
        last_line_(begin > 0 ? begin - 1 : 0) {}

  /// Throws "FILE: damaged $SECTION section (line N): WHAT; FIX" at the last line read.
  [[noreturn]] void fail(std::string_view what) const {
    throw InputError(fmt::format("{}: damaged ${} section (line {}): {}; {}", file_.string(), section_,
                                 lines_[last_line_].number, what, kMshFix));
  }

  /// The next token, from this line or the following ones (Gmsh reads with fscanf).
  std::optional<std::string_view> next() {
    while (line_ < end_) {
      const std::string_view s = lines_[line_].text;
      while (pos_ < s.size() && std::isspace(static_cast<unsigned char>(s[pos_]))) ++pos_;
      if (pos_ < s.size()) {
        std::size_t e = pos_;
        while (e < s.size() && !std::isspace(static_cast<unsigned char>(s[e]))) ++e;
        const std::string_view token = s.substr(pos_, e - pos_);
        pos_ = e;
        last_line_ = line_;
        return token;
      }
      ++line_;
      pos_ = 0;
    }
    return std::nullopt;
  }

  /// The next whole line that holds anything (and moves past it); empty at the end.
  std::optional<std::string_view> next_line() {
    if (line_ < end_ && pos_ > 0) {
      ++line_;
      pos_ = 0;
    }
    while (line_ < end_ && lines_[line_].text.find_first_not_of(" \t\r") == std::string_view::npos) ++line_;
    if (line_ >= end_) return std::nullopt;
    last_line_ = line_;
    pos_ = lines_[line_].text.size();
    return lines_[line_].text;
  }

  template <class T>
  T parse_integer(std::string_view token, std::string_view what, T lo, T hi) const {
    T value{};
    const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (ec != std::errc() || ptr != token.data() + token.size()) {
      fail(fmt::format("expected {} (an integer), got '{}'", what, excerpt(token)));
    }
    if (value < lo || value > hi) {
      fail(fmt::format("{} must be in [{}, {}], got {}", what, lo, hi, value));
    }
    return value;
  }

  template <class T>
  T integer(std::string_view what, T lo, T hi) {
    const auto token = next();
    if (!token) fail(fmt::format("the section ends where {} was expected", what));
    return parse_integer<T>(*token, what, lo, hi);
  }

  double real(std::string_view what) {
    const auto token = next();
    if (!token) fail(fmt::format("the section ends where {} was expected", what));
    double value = 0.0;
    std::string_view s = *token;
    if (s.size() > 1 && s.front() == '+') s.remove_prefix(1);
    const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
    if (ec != std::errc() || ptr != s.data() + s.size() || !std::isfinite(value)) {
      fail(fmt::format("expected {} (a finite number), got '{}'", what, excerpt(*token)));
    }
    return value;
  }

  void expect_end() {
    if (const auto token = next()) {
      fail(fmt::format("unexpected '{}' after the last entry (the counts do not match the data)", excerpt(*token)));
    }
  }

 private:
  const fs::path& file_;
  std::string section_;
  const std::vector<MshLine>& lines_;
  std::size_t line_, end_;
  std::size_t pos_ = 0;
  std::size_t last_line_;
};

constexpr std::size_t kMaxTag = std::size_t{1} << 62;
constexpr long long kMaxCount = 1LL << 40;

struct MshModel {
  std::array<std::set<int>, 4> entities;  ///< entity tags per dimension (from $Entities)
  bool has_entities = false;
  std::unordered_set<std::size_t> nodes;
  bool has_nodes = false;
};

void read_physical_names(SectionReader& r) {
  const auto first = r.next_line();
  if (!first) r.fail("the section is empty; expected the number of names");
  const std::string_view count_text = *first;
  const int count =
      r.parse_integer<int>(count_text.substr(count_text.find_first_not_of(" \t")), "the number of names", 0, 1 << 30);
  std::set<std::pair<int, int>> seen;
  for (int i = 0; i < count; ++i) {
    const auto line = r.next_line();
    if (!line) {
      r.fail(fmt::format("the section holds {} name(s), its first line announces {}", i, count));
    }
    // DIM TAG "NAME" on one line
    std::string_view rest = *line;
    auto word = [&rest]() {
      const std::size_t b = rest.find_first_not_of(" \t");
      if (b == std::string_view::npos) {
        rest = {};
        return std::string_view{};
      }
      rest.remove_prefix(b);
      const std::size_t e = std::min(rest.find_first_of(" \t"), rest.size());
      const std::string_view w = rest.substr(0, e);
      rest.remove_prefix(e);
      return w;
    };
    const int dim = r.parse_integer<int>(word(), "a dimension", 0, 3);
    const int tag = r.parse_integer<int>(word(), "a physical tag", 1, std::numeric_limits<int>::max());
    const std::size_t b = rest.find_first_not_of(" \t");
    const std::string_view name = b == std::string_view::npos ? std::string_view{} : rest.substr(b);
    if (name.size() < 2 || name.front() != '"' || name.back() != '"' ||
        name.substr(1, name.size() - 2).find('"') != std::string_view::npos) {
      r.fail(fmt::format("expected a quoted name after '{} {}', got '{}'", dim, tag, excerpt(name)));
    }
    if (name.size() - 2 > 255) r.fail("a name is longer than 255 characters");
    if (!seen.emplace(dim, tag).second) {
      r.fail(fmt::format("physical group {} of dimension {} is named twice", tag, dim));
    }
  }
  if (r.next_line()) {
    r.fail(fmt::format("more names than the {} its first line announces", count));
  }
}

void read_entities(SectionReader& r, MshModel& model) {
  std::array<long long, 4> counts{};
  for (int d = 0; d < 4; ++d) {
    counts[static_cast<std::size_t>(d)] = r.integer<long long>(
        std::array<const char*, 4>{"the number of points", "the number of curves", "the number of surfaces",
                                   "the number of volumes"}[static_cast<std::size_t>(d)],
        0, kMaxCount);
  }
  for (int d = 0; d < 4; ++d) {
    for (long long i = 0; i < counts[static_cast<std::size_t>(d)]; ++i) {
      const int tag = r.integer<int>("an entity tag", 1, std::numeric_limits<int>::max());
      if (!model.entities[static_cast<std::size_t>(d)].insert(tag).second) {
        r.fail(fmt::format("entity {} of dimension {} is defined twice", tag, d));
      }
      for (int c = 0; c < (d == 0 ? 3 : 6); ++c) r.real("a coordinate");
      const int physicals = r.integer<int>("the number of physical tags", 0, 1 << 20);
      for (int p = 0; p < physicals; ++p) {
        r.integer<int>("a physical tag", std::numeric_limits<int>::min() + 1, std::numeric_limits<int>::max());
      }
      if (d == 0) continue;
      const int bounding = r.integer<int>("the number of bounding entities", 0, 1 << 24);
      for (int b = 0; b < bounding; ++b) {
        const int btag = r.integer<int>("a bounding entity tag", std::numeric_limits<int>::min() + 1,
                                        std::numeric_limits<int>::max());
        if (!model.entities[static_cast<std::size_t>(d - 1)].count(std::abs(btag))) {
          r.fail(
              fmt::format("entity {} of dimension {} is bounded by entity {} of dimension "
                          "{}, which is not defined",
                          tag, d, std::abs(btag), d - 1));
        }
      }
    }
  }
  r.expect_end();
  model.has_entities = true;
}

void check_entity(SectionReader& r, const MshModel& model, int dim, int tag) {
  if (model.has_entities && !model.entities[static_cast<std::size_t>(dim)].count(tag)) {
    r.fail(
        fmt::format("a block refers to entity {} of dimension {}, which $Entities does not "
                    "define",
                    tag, dim));
  }
}

/// The first line of $Nodes and $Elements: block count, entry count and the tag range, which
/// must be able to hold that many distinct tags.
struct BlockHeader {
  long long blocks = 0, total = 0;
  std::size_t min_tag = 0, max_tag = 0;
};

BlockHeader read_block_header(SectionReader& r, std::string_view entry) {
  BlockHeader h;
  h.blocks = r.integer<long long>(fmt::format("the number of {} blocks", entry), 0, kMaxCount);
  h.total = r.integer<long long>(fmt::format("the number of {}s", entry), 0, kMaxCount);
  h.min_tag = r.integer<std::size_t>(fmt::format("the smallest {} tag", entry), 0, kMaxTag);
  h.max_tag = r.integer<std::size_t>(fmt::format("the largest {} tag", entry), 0, kMaxTag);
  if (h.total > 0 &&
      (h.min_tag < 1 || h.max_tag < h.min_tag || h.max_tag - h.min_tag + 1 < static_cast<std::size_t>(h.total))) {
    r.fail(fmt::format("{} {}s cannot have tags {} to {}", h.total, entry, h.min_tag, h.max_tag));
  }
  return h;
}

void read_nodes(SectionReader& r, MshModel& model) {
  const auto [blocks, total, min_tag, max_tag] = read_block_header(r, "node");
  long long seen = 0;
  for (long long b = 0; b < blocks; ++b) {
    const int dim = r.integer<int>("an entity dimension", 0, 3);
    const int tag = r.integer<int>("an entity tag", 1, std::numeric_limits<int>::max());
    const int parametric = r.integer<int>("the parametric flag", 0, 1);
    const auto count = r.integer<long long>("the number of nodes of a block", 0, total - seen);
    check_entity(r, model, dim, tag);
    for (long long i = 0; i < count; ++i) {
      const auto node = r.integer<std::size_t>("a node tag", std::max<std::size_t>(min_tag, 1), max_tag);
      if (!model.nodes.insert(node).second) r.fail(fmt::format("node {} is defined twice", node));
    }
    const int values = 3 + (parametric ? dim : 0);
    for (long long i = 0; i < count * values; ++i) r.real("a node coordinate");
    seen += count;
  }
  if (seen != total) {
    r.fail(fmt::format("the header announces {} nodes, the blocks hold {}", total, seen));
  }
  r.expect_end();
  model.has_nodes = true;
}

void read_elements(SectionReader& r, const MshModel& model) {
  if (!model.has_nodes) r.fail("$Elements comes before $Nodes");
  const auto [blocks, total, min_tag, max_tag] = read_block_header(r, "element");
  std::unordered_set<std::size_t> tags;
  long long seen = 0;
  for (long long b = 0; b < blocks; ++b) {
    const int dim = r.integer<int>("an entity dimension", 0, 3);
    const int tag = r.integer<int>("an entity tag", 1, std::numeric_limits<int>::max());
    const int type = r.integer<int>("an element type", 1, 1000);
    int type_dim = -1;
    const int nodes = msh_element_node_count(type, &type_dim);
    if (nodes == 0) r.fail(fmt::format("unknown element type {}", type));
    if (type_dim != dim) {
      r.fail(fmt::format("elements of type {} ({}-D) in a block of dimension {}", type, type_dim, dim));
    }
    check_entity(r, model, dim, tag);
    const auto count = r.integer<long long>("the number of elements of a block", 0, total - seen);
    for (long long i = 0; i < count; ++i) {
      const auto element = r.integer<std::size_t>("an element tag", std::max<std::size_t>(min_tag, 1), max_tag);
      if (!tags.insert(element).second) {
        r.fail(fmt::format("element {} is defined twice", element));
      }
      for (int k = 0; k < nodes; ++k) {
        const auto node = r.integer<std::size_t>("a node tag", 1, kMaxTag);
        if (!model.nodes.count(node)) {
          r.fail(fmt::format("element {} uses node {}, which $Nodes does not define", element, node));
        }
      }
    }
    seen += count;
  }
  if (seen != total) {
    r.fail(fmt::format("the header announces {} elements, the blocks hold {}", total, seen));
  }
  r.expect_end();
}

}  // namespace

int msh_element_node_count(int gmsh_type, int* dim) {
  struct Type {
    int nodes, dim;
  };
  // Gmsh's element types 1..31 (GmshDefines.h: MSH_LIN_2 ... MSH_TET_56), 92 and 93.
  static constexpr std::array<Type, 32> types = {{
      {0, -1}, {2, 1},  {3, 2},  {4, 2},  {4, 3}, {8, 3}, {6, 3},  {5, 3},  {3, 1},  {6, 2},  {9, 2},
      {10, 3}, {27, 3}, {18, 3}, {14, 3}, {1, 0}, {8, 2}, {20, 3}, {15, 3}, {13, 3}, {9, 2},  {10, 2},
      {12, 2}, {15, 2}, {15, 2}, {21, 2}, {4, 1}, {5, 1}, {6, 1},  {20, 3}, {35, 3}, {56, 3},
  }};
  Type t{0, -1};
  if (gmsh_type >= 1 && gmsh_type < static_cast<int>(types.size())) {
    t = types[static_cast<std::size_t>(gmsh_type)];
  } else if (gmsh_type == 92) {
    t = {64, 3};
  } else if (gmsh_type == 93) {
    t = {125, 3};
  }
  if (dim) *dim = t.dim;
  return t.nodes;
}

void check_msh_text(std::string_view text, const fs::path& file) {
  const auto blank = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  if (std::all_of(text.begin(), text.end(), blank)) {
    throw_input_error("{}: empty file; expected a Gmsh mesh: {}", file.string(), kMshFix);
  }
  const std::vector<MshLine> lines = split_lines(text);
  if (lines.empty() || lines[0].text != "$MeshFormat") {
    throw_input_error(
        "{}:1: not a Gmsh mesh file (it does not start with $MeshFormat); a .msh "
        "must be a mesh written by Gmsh (format 4.1), a geometry script is given "
        "as 'geo:' with a .geo name",
        file.string());
  }
  if (lines.size() < 3) {
    throw_input_error("{}: damaged $MeshFormat section (line 2): the file ends inside it; {}", file.string(), kMshFix);
  }
  {
    std::istringstream header{std::string(lines[1].text)};
    std::string version, extra;
    int file_type = -1, data_size = -1;
    if (!(header >> version >> file_type >> data_size) || (header >> extra)) {
      throw_input_error(
          "{}: damaged $MeshFormat section (line 2): expected 'VERSION "
          "FILE-TYPE DATA-SIZE', got '{}'; {}",
          file.string(), excerpt(lines[1].text), kMshFix);
    }
    if (file_type == 1) {
      throw_input_error(
          "{}: binary .msh files are not supported (they cannot be checked "
          "before Gmsh reads them); re-export the mesh from Gmsh as ASCII "
          "(option Mesh.Binary = 0, format 4.1)",
          file.string());
    }
    if (version != "4.1" || file_type != 0) {
      throw_input_error(
          "{}: .msh format '{}' (file type {}) is not supported; re-export the "
          "mesh from Gmsh in format 4.1 ASCII (Mesh.MshFileVersion = 4.1)",
          file.string(), excerpt(version), file_type);
    }
    if (data_size != static_cast<int>(sizeof(double))) {
      throw_input_error("{}: damaged $MeshFormat section (line 2): data size {}, expected {}; {}", file.string(),
                        data_size, sizeof(double), kMshFix);
    }
    if (lines[2].text != "$EndMeshFormat") {
      throw_input_error(
          "{}: damaged $MeshFormat section (line 3): expected $EndMeshFormat, got "
          "'{}'; {}",
          file.string(), excerpt(lines[2].text), kMshFix);
    }
  }

  MshModel model;
  std::set<std::string> done;
  std::size_t i = 3;
  while (i < lines.size()) {
    const MshLine& head = lines[i];
    if (head.text.empty()) {
      ++i;
      continue;
    }
    if (head.text.front() != '$' || head.text.starts_with("$End")) {
      throw_input_error(
          "{}: unexpected '{}' at line {} outside of a section (each section is "
          "$Name ... $EndName); {}",
          file.string(), excerpt(head.text), head.number, kMshFix);
    }
    const std::string name(head.text.substr(1));
    const std::string end_marker = "$End" + name;
    const std::string shown = excerpt(name);  // the name as read: no raw bytes in a message
    std::size_t end = i + 1;
    while (end < lines.size() && !(lines[end].text.starts_with("$"))) ++end;
    if (end >= lines.size()) {
      throw_input_error("{}: damaged ${} section (line {}): no $End{} line; {}", file.string(), shown, head.number,
                        shown, kMshFix);
    }
    if (lines[end].text != end_marker) {
      throw_input_error("{}: damaged ${} section (line {}): expected $End{}, got '{}'; {}", file.string(), shown,
                        lines[end].number, shown, excerpt(lines[end].text), kMshFix);
    }
    static const std::set<std::string> checked = {"PhysicalNames", "Entities", "Nodes", "Elements"};
    static const std::set<std::string> unsupported = {
        "MeshFormat", "PartitionedEntities", "Periodic",        "GhostElements",       "Parametrizations",
        "NodeData",   "ElementData",         "ElementNodeData", "InterpolationScheme", "Comments"};
    if (!checked.count(name)) {
      throw_input_error(
          "{}: {} section ${} at line {}; shellflow reads meshes with the sections "
          "$MeshFormat, $PhysicalNames, $Entities, $Nodes and $Elements only: {}",
          file.string(), unsupported.count(name) ? "unsupported" : "unknown", shown, head.number, kMshFix);
    }
    if (!done.insert(name).second) {
      throw_input_error("{}: a second ${} section at line {}; {}", file.string(), name, head.number, kMshFix);
    }
    SectionReader reader(file, name, lines, i + 1, end);
    if (name == "PhysicalNames") {
      read_physical_names(reader);
    } else if (name == "Entities") {
      if (done.count("Nodes")) reader.fail("$Entities comes after $Nodes");
      read_entities(reader, model);
    } else if (name == "Nodes") {
      read_nodes(reader, model);
    } else {
      read_elements(reader, model);
    }
    i = end + 1;
  }
}

}  // namespace shellflow::mesh
