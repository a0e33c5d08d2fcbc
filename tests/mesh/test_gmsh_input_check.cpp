// Files are checked before Gmsh reads them: a .geo runs no commands, a .msh is read only as a
// mesh, and a damaged .msh is an InputError rather than a crash inside Gmsh 4.8.
#include <gmsh.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "mesh_test_util.h"
#include "shellflow/core/error.h"
#include "shellflow/core/version.h"
#include "shellflow/mesh/gmsh_input_check.h"
#include "shellflow/mesh/gmsh_io.h"

using namespace shellflow;
using namespace shellflow::mesh;
namespace fs = std::filesystem;

namespace {
const fs::path panel_dir = fs::path(shellflow::source_dir) / "cases" / "panel_flutter";

/// A scratch folder of this test process (ctest runs tests of this file in parallel processes,
/// which must not remove each other's files).
fs::path fresh_dir(const std::string& name) {
  auto dir = fs::temp_directory_path() / ("shellflow_test_input_check_" + std::to_string(getpid()) + "_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

/// The message of the InputError `f` throws ("" when it throws none).
std::string input_error(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

const std::string panel_geo = read(panel_dir / "panel_strip.geo");

/// A panel strip .geo (30 lines) with `extra` appended as line 30 and on.
fs::path geo_with(const fs::path& dir, const std::string& name, const std::string& extra) {
  const fs::path geo = dir / name;
  write(geo, panel_geo + extra + "\n");
  return geo;
}

int line_count(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

/// A good .msh 4.1 of the panel strip (cubic triangles), written by Gmsh.
const std::string& good_msh() {
  static const std::string text = [] {
    const auto dir = fresh_dir("good");
    generate_mesh(panel_dir / "panel_strip.geo", with_order(3, 1.0, dir / "strip.msh"), "shell");
    return read(dir / "strip.msh");
  }();
  return text;
}

/// good_msh() with line `line` (1-based) replaced by `replacement` (no line when empty
/// and `remove`).
std::string msh_with_line(int line, const std::string& replacement, bool remove = false) {
  std::istringstream in(good_msh());
  std::string out, l;
  for (int n = 1; std::getline(in, l); ++n) {
    if (n == line) {
      if (!remove) out += replacement + "\n";
    } else {
      out += l + "\n";
    }
  }
  return out;
}

int line_of(const std::string& text, const std::string& needle) {
  std::istringstream in(text);
  std::string l;
  for (int n = 1; std::getline(in, l); ++n)
    if (l == needle) return n;
  return 0;
}
}  // namespace

TEST(GeoScan, ShellCommandsAreRefusedAndRunNothing) {
  const auto dir = fresh_dir("system");
  const int line = line_count(panel_geo) + 1;
  for (std::string command : {"System", "SystemCall", "NonBlockingSystemCall"}) {
    const fs::path marker = dir / ("INJECTED_" + command);
    const fs::path geo = geo_with(dir, command + ".geo", command + " \"touch '" + marker.string() + "'\";");
    for (auto f : std::vector<std::function<void()>>{[&] { physical_group_names(geo); },
                                                     [&] { generate_mesh(geo, with_order(1), "shell"); }}) {
      const std::string msg = input_error(f);
      EXPECT_NE(msg.find(geo.string() + ":" + std::to_string(line) + ": Gmsh command '" + command + "'"),
                std::string::npos)
          << msg;
      EXPECT_NE(msg.find("remove it"), std::string::npos) << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
    EXPECT_FALSE(fs::exists(marker)) << command << " ran";
  }
  const fs::path geo = geo_with(dir, "onelab.geo", "OnelabRun(\"x\", \"touch y\");");
  EXPECT_NE(input_error([&] { physical_group_names(geo); }).find("'OnelabRun' runs"), std::string::npos);
}

TEST(GeoScan, FileWritingCommandsAreRefused) {
  const auto dir = fresh_dir("writes");
  for (std::string extra : {"Save \"out.msh\";", "Print \"out.png\";", "CreateDir \"d\";",
                            "Printf(\"%g\", 1) > \"out.txt\";", "Printf(\"x\") >> \"out.txt\";", "Exit;"}) {
    const fs::path geo = geo_with(dir, "w.geo", extra);
    const std::string msg = input_error([&] { physical_group_names(geo); });
    EXPECT_NE(msg.find("w.geo:" + std::to_string(line_count(panel_geo) + 1) + ":"), std::string::npos)
        << extra << ": " << msg;
  }
  EXPECT_FALSE(fs::exists(dir / "out.msh"));
  EXPECT_FALSE(fs::exists(dir / "out.txt"));
  EXPECT_FALSE(fs::exists(dir / "d"));
}

TEST(GeoScan, CommandWordsInCommentsAndStringsAreText) {
  const auto dir = fresh_dir("comments");
  const fs::path geo = geo_with(dir, "ok.geo",
                                "// System \"touch x\";\n"
                                "/* SystemCall \"touch y\";\n   OnelabRun */\n"
                                "Printf(\"System and Include are words here\");\n");
  const auto names = physical_group_names(geo);
  EXPECT_EQ(names.size(), 4u);
}

TEST(GeoScan, IncludesStayInTheFolderAndAreScanned) {
  const auto dir = fresh_dir("include");
  const auto sub = dir / "case";
  fs::create_directories(sub);
  write(dir / "outside.geo", "x = 1;\n");
  write(sub / "part.geo", "y = 2;\n");
  write(sub / "evil.geo", "z = 3;\nSystem \"touch '" + (dir / "INJECTED").string() + "'\";\n");

  EXPECT_EQ(physical_group_names(geo_with(sub, "good.geo", "Include \"part.geo\";")).size(), 4u);

  std::string msg = input_error([&] { physical_group_names(geo_with(sub, "abs.geo", "Include \"/etc/hostname\";")); });
  EXPECT_NE(msg.find("abs.geo:" + std::to_string(line_count(panel_geo) + 1) +
                     ": 'Include' of "
                     "the absolute path"),
            std::string::npos)
      << msg;
  msg = input_error([&] { physical_group_names(geo_with(sub, "up.geo", "Include \"../outside.geo\";")); });
  EXPECT_NE(msg.find("leaves the folder"), std::string::npos) << msg;
  msg = input_error([&] { physical_group_names(geo_with(sub, "sub.geo", "Include \"./x/../../outside.geo\";")); });
  EXPECT_NE(msg.find("leaves the folder"), std::string::npos) << msg;
  msg = input_error([&] { physical_group_names(geo_with(sub, "merge.geo", "Merge \"../outside.geo\";")); });
  EXPECT_NE(msg.find("'Merge' of '../outside.geo' leaves the folder"), std::string::npos) << msg;
  msg = input_error([&] { physical_group_names(geo_with(sub, "expr.geo", "Include StrCat(\"/etc/\", \"passwd\");")); });
  EXPECT_NE(msg.find("one quoted relative path"), std::string::npos) << msg;
  // The included file is scanned too, and named in the message.
  msg = input_error([&] { physical_group_names(geo_with(sub, "inc.geo", "Include \"evil.geo\";")); });
  EXPECT_NE(msg.find((sub / "evil.geo").string() + ":2: Gmsh command 'System'"), std::string::npos) << msg;
  EXPECT_FALSE(fs::exists(dir / "INJECTED"));
}

TEST(GeoScan, TheOptionFileGmshMergesIsScanned) {
  const auto dir = fresh_dir("opt");
  const fs::path geo = geo_with(dir, "s.geo", "");
  write(dir / "s.geo.opt", "General.Terminal = 0;\nSystem \"touch '" + (dir / "INJECTED").string() + "'\";\n");
  const std::string msg = input_error([&] { physical_group_names(geo); });
  EXPECT_NE(msg.find("s.geo.opt:2: Gmsh command 'System'"), std::string::npos) << msg;
  EXPECT_FALSE(fs::exists(dir / "INJECTED"));
}

TEST(GeoScan, AStringCannotHideCodeFromIfSkipping) {
  // Gmsh skips a false If block without reading strings: the "EndIf" in the string ends the
  // block for Gmsh, which then runs what the scanner sees as the rest of the string.
  const auto dir = fresh_dir("skip");
  const fs::path geo =
      geo_with(dir, "skip.geo", "If (0)\n \"EndIf\nSystem \"touch '" + (dir / "INJECTED").string() + "'\";\n\"\nEndIf");
  const std::string msg = input_error([&] { physical_group_names(geo); });
  EXPECT_NE(msg.find("a string holds 'EndIf'"), std::string::npos) << msg;
  EXPECT_FALSE(fs::exists(dir / "INJECTED"));
}

TEST(MshCheck, AScriptNamedMshIsNotAMeshAndRunsNothing) {
  const auto dir = fresh_dir("renamed");
  const fs::path msh = dir / "renamed.msh";
  write(msh, panel_geo + "System \"touch '" + (dir / "INJECTED").string() + "'\";\n");
  for (auto f :
       std::vector<std::function<void()>>{[&] { physical_group_names(msh); }, [&] { read_msh(msh, "shell"); }}) {
    const std::string msg = input_error(f);
    EXPECT_NE(msg.find(msh.string() + ":1: not a Gmsh mesh file"), std::string::npos) << msg;
  }
  EXPECT_FALSE(fs::exists(dir / "INJECTED"));
}

TEST(MshCheck, EmptyFileIsReportedAsEmpty) {
  const auto dir = fresh_dir("empty");
  write(dir / "empty.msh", "");
  write(dir / "blank.msh", "\n  \n");
  for (const char* name : {"empty.msh", "blank.msh"}) {
    const std::string msg = input_error([&] { physical_group_names(dir / name); });
    EXPECT_NE(msg.find(std::string(name) + ": empty file; "), std::string::npos) << msg;
    EXPECT_NE(input_error([&] { read_msh(dir / name, "x"); }).find("empty file"), std::string::npos);
  }
}

TEST(MshCheck, GoodMeshesPass) {
  EXPECT_NO_THROW(
      check_msh_file(fs::path(shellflow::source_dir) / "tests" / "case" / "data" / "panel_strip.msh"));  // header only
  const auto dir = fresh_dir("goodpass");
  write(dir / "strip.msh", good_msh());
  EXPECT_NO_THROW(check_msh_file(dir / "strip.msh"));
  EXPECT_EQ(read_msh(dir / "strip.msh", "shell").num_cells(), 40);
  // CRLF line ends are fine.
  write(dir / "crlf.msh", std::regex_replace(good_msh(), std::regex("\n"), "\r\n"));
  EXPECT_NO_THROW(check_msh_file(dir / "crlf.msh"));
}

TEST(MshCheck, DamagedFilesAreOneLineErrorsNotCrashes) {
  // Several of these crash Gmsh 4.8 (SIGSEGV in GModel::setPhysicalName) when it reads them.
  const std::string& good = good_msh();
  const int names = line_of(good, "$PhysicalNames");
  const int end_names = line_of(good, "$EndPhysicalNames");
  const int nodes = line_of(good, "$Nodes");
  const int elements = line_of(good, "$Elements");
  const int end_nodes = line_of(good, "$EndNodes");
  ASSERT_EQ(end_nodes + 1, elements);
  ASSERT_GT(names, 0);
  ASSERT_GT(elements, nodes);
  struct Case {
    std::string text, expected;
  };
  const std::vector<Case> cases = {
      {msh_with_line(names + 2, "99 1 \"bad\""), "damaged $PhysicalNames section (line " + std::to_string(names + 2) +
                                                     "): a dimension must be in [0, 3], got 99"},
      {msh_with_line(end_names, "99 1 \"bad\""), "damaged $PhysicalNames section (line " +
                                                     std::to_string(end_names + 1) +
                                                     "): expected $EndPhysicalNames, got '$Entities'"},
      {msh_with_line(end_names, "$EndPhysicalNam"), "damaged $PhysicalNames section (line " +
                                                        std::to_string(end_names) +
                                                        "): expected $EndPhysicalNames, got '$EndPhysicalNam'"},
      {msh_with_line(end_names, "", true), "damaged $PhysicalNames section"},
      {msh_with_line(names + 1, "x4"),
       "damaged $PhysicalNames section (line " + std::to_string(names + 1) + "): expected the number"},
      {msh_with_line(names + 1, "40"), "its first line announces 40"},
      {msh_with_line(names + 2, "1 1 \"leading_edge"), "expected a quoted name"},
      {msh_with_line(nodes + 1, "9 244 1"), "damaged $Nodes section"},
      {msh_with_line(end_nodes, "$EndNode"), "expected $EndNodes, got '$EndNode'"},
      {msh_with_line(elements + 3, "1 1 2 5 99999"), "damaged $Elements section (line " + std::to_string(elements + 3) +
                                                         "): element 1 uses node 99999, which $Nodes does not define"},
      {msh_with_line(elements + 2, "1 1 77 1"), "unknown element type 77"},
      {good.substr(0, good.size() / 2), "no $End"},
      {msh_with_line(2, "4.1 1 8"), "binary .msh files are not supported"},
      {msh_with_line(2, "2.2 0 8"), ".msh format '2.2' (file type 0) is not supported"},
      {msh_with_line(names, "$Periodic"), "expected $EndPeriodic"},
      {msh_with_line(3, "$EndMeshFormat\n$Foo\n1\n$EndFoo"), "unknown section $Foo at line 4"},
  };
  const auto dir = fresh_dir("damaged");
  int i = 0;
  for (const auto& c : cases) {
    const fs::path msh = dir / ("damaged_" + std::to_string(i++) + ".msh");
    write(msh, c.text);
    for (auto f :
         std::vector<std::function<void()>>{[&] { physical_group_names(msh); }, [&] { read_msh(msh, "shell"); }}) {
      const std::string msg = input_error(f);
      EXPECT_EQ(msg.rfind(msh.string() + ":", 0), 0u) << msg;
      EXPECT_NE(msg.find(c.expected), std::string::npos) << msh << ": " << msg;
      EXPECT_NE(msg.find("re-export the mesh"), std::string::npos) << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
  }
}

TEST(MshCheck, ElementNodeCountsMatchGmsh) {
  gmsh::initialize(0, nullptr, false);
  gmsh::option::setNumber("General.Terminal", 0);
  for (int type = 1; type <= 93; ++type) {
    if (type > 31 && type < 92) continue;
    int dim = -1;
    const int nodes = msh_element_node_count(type, &dim);
    std::string name;
    int gdim = 0, order = 0, gnodes = 0, primary = 0;
    std::vector<double> local;
    gmsh::model::mesh::getElementProperties(type, name, gdim, order, gnodes, local, primary);
    EXPECT_EQ(nodes, gnodes) << "type " << type << " " << name;
    EXPECT_EQ(dim, gdim) << "type " << type << " " << name;
  }
  gmsh::finalize();
  EXPECT_EQ(msh_element_node_count(77), 0);
}
