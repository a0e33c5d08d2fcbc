// The checks of gmsh_input_check.h for `.geo` scripts and option files, and the dispatch by
// extension; the `.msh` checks are in gmsh_msh_check.cpp.
#include "shellflow/mesh/gmsh_input_check.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "shellflow/core/error.h"

namespace shellflow::mesh {
namespace fs = std::filesystem;

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string extension_of(const fs::path& file) { return lower(file.extension().string()); }

std::string read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    throw_input_error("{}: cannot open the file (check the path and its permissions)", file.string());
  }
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// The folder of `file` ("." for a bare file name, so that paths can be joined to it).
fs::path folder_of(const fs::path& file) { return file.has_parent_path() ? file.parent_path() : fs::path("."); }

bool is_cad_extension(const std::string& ext) {
  return ext == ".step" || ext == ".stp" || ext == ".iges" || ext == ".igs" || ext == ".brep";
}

// ---- .geo scripts ---------------------------------------------------------------------------

struct GeoToken {
  enum Kind { identifier, string, symbol } kind;
  std::string text;
  int line;
};

/// Tokens of a Gmsh script as Gmsh's lexer sees them: `//` and `/* */` comments skipped,
/// strings run from `"` to the next `"` (Gmsh has no escapes in strings), identifiers are
/// [A-Za-z_][A-Za-z0-9_]*; digits and other characters are one-character symbols (so that
/// `2System` still shows `System`).
std::vector<GeoToken> geo_tokens(std::string_view s) {
  std::vector<GeoToken> out;
  int line = 1;
  std::size_t i = 0;
  const std::size_t n = s.size();
  auto is_ident_start = [](char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; };
  auto is_ident = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  while (i < n) {
    const char c = s[i];
    if (c == '\n') {
      ++line;
      ++i;
    } else if (std::isspace(static_cast<unsigned char>(c))) {
      ++i;
    } else if (c == '/' && i + 1 < n && s[i + 1] == '/') {
      while (i < n && s[i] != '\n') ++i;
    } else if (c == '/' && i + 1 < n && s[i + 1] == '*') {
      i += 2;
      while (i < n && !(s[i] == '*' && i + 1 < n && s[i + 1] == '/')) {
        if (s[i] == '\n') ++line;
        ++i;
      }
      i = std::min(n, i + 2);
    } else if (c == '"') {
      const int start_line = line;
      std::size_t j = i + 1;
      while (j < n && s[j] != '"') {
        if (s[j] == '\n') ++line;
        ++j;
      }
      out.push_back({GeoToken::string, std::string(s.substr(i + 1, j - i - 1)), start_line});
      i = std::min(n, j + 1);
    } else if (is_ident_start(c)) {
      std::size_t j = i;
      while (j < n && is_ident(s[j])) ++j;
      out.push_back({GeoToken::identifier, std::string(s.substr(i, j - i)), line});
      i = j;
    } else {
      out.push_back({GeoToken::symbol, std::string(1, c), line});
      ++i;
    }
  }
  return out;
}

constexpr std::string_view kGeoFix =
    "shellflow runs no commands from a geometry: remove it from the script (run such steps "
    "yourself before the case)";

struct GeoScanner {
  fs::path root;                          ///< folder of the top-level file: included/merged files must stay inside
  std::vector<fs::path> stack;            ///< files being scanned (include cycles)
  std::vector<fs::path>* read = nullptr;  ///< when set, receives every file Gmsh would read

  [[noreturn]] static void fail(const fs::path& file, int line, std::string_view what) {
    throw InputError(fmt::format("{}:{}: {}", file.string(), line, what));
  }

  /// A file named by Include/Merge/ShapeFromFile in `file`: a relative path that stays in
  /// the top-level folder and exists.
  fs::path referenced_file(const fs::path& file, const GeoToken& command, const GeoToken& name) const {
    const fs::path given(name.text);
    if (name.text.empty() || given.is_absolute()) {
      fail(file, name.line,
           fmt::format("'{}' of the absolute path '{}': a script may only {} files of its own "
                       "folder; copy the file next to the .geo and name it relatively",
                       command.text, name.text, lower(command.text)));
    }
    const fs::path target = (folder_of(file) / given).lexically_normal();
    std::error_code ec_root, ec_target;
    const fs::path real_root = fs::weakly_canonical(root, ec_root);
    const fs::path real_target = fs::weakly_canonical(target, ec_target);
    const fs::path rel = real_target.lexically_relative(real_root);
    if (ec_root || ec_target || rel.empty() || *rel.begin() == "..") {
      fail(file, name.line,
           fmt::format("'{}' of '{}' leaves the folder of the geometry ({}); a script may only "
                       "{} files of its own folder: copy the file there",
                       command.text, name.text, root.string(), lower(command.text)));
    }
    std::error_code ec;
    if (!fs::is_regular_file(target, ec)) {
      fail(file, name.line,
           fmt::format("'{}' of '{}': file not found (looked for '{}')", command.text, name.text, target.string()));
    }
    return target;
  }

  void scan(const fs::path& file) {
    std::error_code ec;
    const fs::path real = fs::weakly_canonical(file, ec);
    if (std::find(stack.begin(), stack.end(), real) != stack.end()) {
      throw_input_error("{}: the script includes itself (through {}); remove the cycle", file.string(),
                        stack.back().string());
    }
    if (stack.size() > 32) {
      throw_input_error("{}: more than 32 nested Include/Merge levels; flatten the scripts", file.string());
    }
    stack.push_back(real);
    if (read) read->push_back(file);
    const std::string text = read_text(file);
    if (!text.empty() && text.front() == '$') {
      throw_input_error(
          "{}:1: looks like a Gmsh mesh or data file, not a .geo script (Gmsh would "
          "read it as a mesh); give a mesh as 'msh:' with a .msh name",
          file.string());
    }
    const std::vector<GeoToken> tokens = geo_tokens(text);
    for (std::size_t k = 0; k < tokens.size(); ++k) {
      const GeoToken& t = tokens[k];
      if (t.kind == GeoToken::string) {
        // Gmsh skips the inside of a false If, an empty For and a Function body without
        // reading strings: a block end or a comment opener inside a string would make it
        // resume where this scanner sees a string.
        for (std::string_view word : {"EndIf", "Else", "EndFor", "Return", "/*", "//"}) {
          if (t.text.find(word) != std::string::npos) {
            fail(file, t.line,
                 fmt::format("a string holds '{}', which Gmsh's If/For/Function skipping reads "
                             "as script text, so the script cannot be checked; take '{}' out "
                             "of the string",
                             word, word));
          }
        }
        continue;
      }
      if (t.kind != GeoToken::identifier) continue;
      const std::string& w = t.text;
      if (w == "System" || w == "SystemCall" || w == "NonBlockingSystemCall") {
        fail(file, t.line, fmt::format("Gmsh command '{}' runs a shell command; {}", w, kGeoFix));
      }
      if (w == "OnelabRun") {
        fail(file, t.line, fmt::format("Gmsh command '{}' runs an external program; {}", w, kGeoFix));
      }
      if (w == "Print" || w == "Save" || w == "CreateDir") {
        fail(file, t.line, fmt::format("Gmsh command '{}' writes files; {}", w, kGeoFix));
      }
      if (w == "Exit") {
        fail(file, t.line, fmt::format("Gmsh command 'Exit' would end shellflow; {}", kGeoFix));
      }
      if (w == "Printf") {
        // Printf(...) > "file" and >> "file" write files.
        std::size_t j = k + 1;
        int depth = 0;
        for (; j < tokens.size(); ++j) {
          if (tokens[j].kind != GeoToken::symbol) continue;
          if (tokens[j].text == "(") ++depth;
          if (tokens[j].text == ")" && --depth <= 0) break;
          if (tokens[j].text == ";" && depth <= 0) break;
        }
        if (j + 1 < tokens.size() && tokens[j + 1].kind == GeoToken::symbol && tokens[j + 1].text == ">") {
          fail(file, t.line, fmt::format("Printf(...) > \"file\" writes a file; {}", kGeoFix));
        }
        continue;
      }
      const bool include = w == "Include";
      const bool merge = w == "Merge" || w == "MergeWithBoundingBox";
      const bool shape = w == "ShapeFromFile";
      if (!include && !merge && !shape) continue;
      std::size_t j = k + 1;
      if (shape && j < tokens.size() && tokens[j].text == "(" && tokens[j].kind == GeoToken::symbol) ++j;
      const bool literal = j < tokens.size() && tokens[j].kind == GeoToken::string && j + 1 < tokens.size() &&
                           tokens[j + 1].kind == GeoToken::symbol && tokens[j + 1].text == (shape ? ")" : ";");
      if (!literal) {
        fail(file, t.line,
             fmt::format("'{}' must name its file as one quoted relative path (e.g. {} "
                         "\"part.geo\";), so that shellflow can check it",
                         w, w));
      }
      const fs::path target = referenced_file(file, t, tokens[j]);
      const std::string ext = extension_of(target);
      if (read && ext != ".geo" && !include) read->push_back(target);  // scan() adds scripts
      if (include) {
        scan(target);  // Gmsh parses an included file as a script whatever its name
      } else if (shape) {
        if (!is_cad_extension(ext)) {
          fail(file, t.line, fmt::format("ShapeFromFile of '{}': expected a STEP, IGES or BREP file", tokens[j].text));
        }
      } else if (ext == ".geo") {
        scan(target);
        scan_option_files(target);
      } else if (ext == ".msh") {
        check_msh_file(target);
        scan_option_files(target);
      } else if (is_cad_extension(ext)) {
        scan_option_files(target);
      } else {
        fail(file, t.line,
             fmt::format("Merge of '{}': shellflow merges only .geo, .msh, STEP, IGES and BREP "
                         "files",
                         tokens[j].text));
      }
    }
    stack.pop_back();
  }

  /// Gmsh merges `FILE.opt` (then `FILE.opt.opt`, ...) after every file it opens or merges.
  void scan_option_files(const fs::path& file) {
    std::error_code ec;
    fs::path opt = file;
    for (int level = 0; level < 8; ++level) {
      opt += ".opt";
      if (!fs::exists(opt, ec)) return;
      scan(opt);
    }
    throw_input_error("{}: too many nested option files; remove them", opt.string());
  }
};

}  // namespace

void check_msh_file(const fs::path& file) { check_msh_text(read_text(file), file); }

namespace {

void check_input(const fs::path& file, std::vector<fs::path>* read) {
  const std::string ext = extension_of(file);
  GeoScanner scanner{folder_of(file), {}, read};
  if (ext == ".msh") {
    check_msh_file(file);
    if (read) read->push_back(file);
  } else if (ext == ".geo") {
    scanner.scan(file);
  } else if (is_cad_extension(ext)) {
    if (read) read->push_back(file);
  } else {
    throw_input_error(
        "{}: Gmsh would read a '{}' file as a script or in an unchecked format; "
        "give a .geo script, a .msh mesh (format 4.1) or a STEP/IGES/BREP file",
        file.string(), ext.empty() ? std::string("(no extension)") : ext);
  }
  scanner.stack.clear();
  scanner.scan_option_files(file);
}

}  // namespace

void check_gmsh_input(const fs::path& file) { check_input(file, nullptr); }

std::vector<fs::path> gmsh_input_files(const fs::path& file) {
  std::vector<fs::path> read;
  check_input(file, &read);
  return read;
}

void check_gmsh_option_files(const fs::path& file) {
  GeoScanner scanner{folder_of(file), {}, nullptr};
  scanner.scan_option_files(file);
}

}  // namespace shellflow::mesh
