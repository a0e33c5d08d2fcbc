// VTU writer: a mesh with one curved cell of every supported type, point and cell fields of
// 1, 2 and 3 components and a time is written, then read back by meshio and by a raw
// parser of the appended block (data/check_vtu.py), which checks that every VTK-ordered
// node sits where VTK's reference element puts it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "io_test_util.h"
#include "shellflow/core/error.h"
#include "shellflow/io/vtu_writer.h"

namespace shellflow::io {
namespace {

using test::TempDir;

const std::vector<int> kAllTypes = {15, 1, 8, 26, 2, 9, 21, 4, 11, 29};
const std::string kOddName = "a<b>&\"c'd";  // must survive XML escaping

/// Curved map of cell c: F_c(xi) = b_c + A xi + 0.15 q(xi) (same recipe as check_vtu.py).
Vec3 place_node(int c, const Vec3& xi) {
  Mat3 a;
  a << 1.0, 0.3, 0.2, 0.1, 1.2, 0.4, -0.2, 0.1, 0.9;
  const Vec3 b(2.0 * c, -1.0 * c, 0.5 * c);
  const Vec3 q(xi[1] * xi[2], xi[0] * xi[2] + xi[0] * xi[0], xi[0] * xi[1] - xi[1] * xi[1]);
  return b + a * xi + 0.15 * q;
}

/// The test mesh: cell c has Gmsh type types[c]; its nodes are placed at F_c of Gmsh's
/// reference positions (from the Gmsh API, not from the writer's tables) and numbered in
/// a scrambled order so that connectivity is not the identity.
struct TestMesh {
  std::vector<Vec3> points;
  std::vector<std::vector<Index>> connectivity;  // per cell, Gmsh order
  std::vector<double> pressure, velocity, pair, odd, cell_id, cell_vec;

  explicit TestMesh(const std::vector<int>& types) {
    std::vector<Vec3> nodes;  // in cell-by-cell order
    for (std::size_t c = 0; c < types.size(); ++c) {
      const bool line = types[c] == 1 || types[c] == 8 || types[c] == 26;
      const auto ref = test::gmsh_api_reference_nodes(types[c]);
      std::vector<Index> conn;
      for (std::size_t i = 0; i < ref.size() / 3; ++i) {
        Vec3 xi(ref[3 * i], ref[3 * i + 1], ref[3 * i + 2]);
        if (line) xi[0] = 0.5 * (xi[0] + 1.0);  // Gmsh lines run over [-1, 1]
        conn.push_back(static_cast<Index>(nodes.size()));
        nodes.push_back(place_node(static_cast<int>(c), xi));
      }
      connectivity.push_back(conn);
    }
    const auto n = static_cast<Index>(nodes.size());
    // a bijection, as 11 is prime and shares no factor with any n used here (63, 1..20)
    auto scramble = [n](Index g) { return (11 * g + 5) % n; };
    points.resize(nodes.size());
    for (Index g = 0; g < n; ++g) {
      points[static_cast<std::size_t>(scramble(g))] = nodes[static_cast<std::size_t>(g)];
    }
    for (auto& conn : connectivity) {
      for (auto& v : conn) v = scramble(v);
    }
    for (const Vec3& x : points) {
      const double s = x[0] + 2.0 * x[1] - 3.0 * x[2] + x[0] * x[1];
      pressure.push_back(s);
      velocity.insert(velocity.end(), {x[1], -x[0], x[0] * x[2]});
      pair.insert(pair.end(), {x[0], x[2]});
      odd.push_back(s + 1.0);
    }
    for (std::size_t c = 0; c < types.size(); ++c) {
      const double cd = static_cast<double>(c);
      cell_id.push_back(cd + 0.5);
      cell_vec.insert(cell_vec.end(), {cd, 2.0 * cd, -1.0 * cd});
    }
  }

  VtuGrid grid(const std::vector<int>& types) const {
    VtuGrid g;
    g.points = flat(points);
    for (std::size_t c = 0; c < types.size(); ++c) g.cells.push_back({types[c], connectivity[c]});
    g.point_fields = {{"pressure", 1, pressure}, {"velocity", 3, velocity}, {"pair", 2, pair}, {kOddName, 1, odd}};
    g.cell_fields = {{"cell id", 1, cell_id}, {"cell vec", 3, cell_vec}};
    g.time = 0.1;
    return g;
  }
};

/// Argument of check_vtu.py: "FILE:T1,T2,..." (the Gmsh types of the file's cells).
std::string check_arg(const std::filesystem::path& file, const std::vector<int>& types) {
  std::string arg = file.string() + ":";
  for (std::size_t i = 0; i < types.size(); ++i) {
    if (i > 0) arg += ',';
    arg += std::to_string(types[i]);
  }
  return arg;
}

TEST(VtuWriter, EveryCellTypeReadsBackWithNodesInVtkOrder) {
  TempDir dir("vtu");
  const TestMesh mesh(kAllTypes);
  ASSERT_EQ(mesh.points.size(), 63u);
  const auto file = dir / "mixed.vtu";
  write_vtu(file, mesh.grid(kAllTypes));

  const auto r = test::run_python("check_vtu.py", {check_arg(file, kAllTypes)});
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST(VtuWriter, SingleTypeFilesReadBack) {
  // One file per cell type: meshio handles a file holding a single block (starting at
  // offset 0) differently from the mixed case.
  TempDir dir("vtu1");
  std::vector<std::string> args;
  for (int type : kAllTypes) {
    const std::vector<int> types = {type};
    const TestMesh mesh(types);
    const auto file = dir / ("type" + std::to_string(type) + ".vtu");
    write_vtu(file, mesh.grid(types));
    args.push_back(check_arg(file, types));
  }
  const auto r = test::run_python("check_vtu.py", args);
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST(VtuWriter, LeavesNoTemporaryFileAndOverwrites) {
  TempDir dir("vtu-tmp");
  const TestMesh mesh(kAllTypes);
  const auto file = dir / "sub" / "dir" / "a.vtu";  // parent directories are created
  write_vtu(file, mesh.grid(kAllTypes));
  const auto first = test::read_text(file);
  VtuGrid g = mesh.grid(kAllTypes);
  g.time = 0.5;
  write_vtu(file, g);
  const auto second = test::read_text(file);
  EXPECT_NE(first, second);
  EXPECT_NE(second.find("0.5</DataArray>"), std::string::npos);
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(file.parent_path())) {
    names.push_back(e.path().filename().string());
  }
  EXPECT_EQ(names, std::vector<std::string>{"a.vtu"});
}

TEST(VtuWriter, InconsistentInputThrowsAndKeepsThePreviousFile) {
  TempDir dir("vtu-bad");
  const TestMesh mesh(kAllTypes);
  const auto file = dir / "a.vtu";
  write_vtu(file, mesh.grid(kAllTypes));
  const auto before = test::read_text(file);

  auto expect_error = [&](const VtuGrid& g, const std::string& words) {
    try {
      write_vtu(file, g);
      ADD_FAILURE() << "no error for: " << words;
    } catch (const Error& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(words), std::string::npos) << msg;
      EXPECT_NE(msg.find(file.string()), std::string::npos) << "message names no file: " << msg;
    }
    EXPECT_EQ(test::read_text(file), before);
    EXPECT_FALSE(std::filesystem::exists(file.string() + ".tmp"));
  };

  VtuGrid g = mesh.grid(kAllTypes);
  g.point_fields[1].values = g.point_fields[1].values.first(5);
  expect_error(g, "'velocity' has 5 values");

  g = mesh.grid(kAllTypes);
  g.cell_fields.push_back({"cell id", 1, mesh.cell_id});
  expect_error(g, "two cell fields are named 'cell id'");

  g = mesh.grid(kAllTypes);
  g.point_fields[0].name.clear();
  expect_error(g, "empty name");

  g = mesh.grid(kAllTypes);
  const std::vector<Index> bad_tet = {0, 1, 2, 63};
  g.cells = {{4, bad_tet}};
  g.cell_fields.clear();
  expect_error(g, "refers to point 63");

  g = mesh.grid(kAllTypes);
  const std::vector<Index> quad = {0, 1, 2, 3};
  g.cells = {{3, quad}};
  g.cell_fields.clear();
  expect_error(g, "Gmsh element type 3");

  g = mesh.grid(kAllTypes);
  const std::vector<Index> short_tri = {0, 1, 2, 3};
  g.cells = {{2, short_tri}};
  g.cell_fields.clear();
  expect_error(g, "not a multiple of 3");

  g = mesh.grid(kAllTypes);
  g.time = std::nan("");
  expect_error(g, "not finite");
}

TEST(VtuWriter, FlatViewsVec3AsXyzTriples) {
  const std::vector<Vec3> v = {Vec3(1, 2, 3), Vec3(4, 5, 6)};
  const auto f = flat(v);
  EXPECT_EQ(std::vector<double>(f.begin(), f.end()), (std::vector<double>{1, 2, 3, 4, 5, 6}));
  EXPECT_TRUE(flat(std::span<const Vec3>{}).empty());
}

TEST(VtuWriter, XmlEscapeCoversAttributeSpecials) {
  EXPECT_EQ(xml_escape(kOddName), "a&lt;b&gt;&amp;&quot;c&apos;d");
  EXPECT_EQ(xml_escape("plain_name 1.0"), "plain_name 1.0");
}

}  // namespace
}  // namespace shellflow::io
