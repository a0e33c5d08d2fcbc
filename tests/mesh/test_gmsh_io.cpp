#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>

#include "mesh_test_util.h"
#include "shellflow/core/error.h"
#include "shellflow/core/version.h"
#include "shellflow/mesh/gmsh_io.h"
#include "shellflow/mesh/quality.h"

using namespace shellflow;
using namespace shellflow::mesh;
namespace fs = std::filesystem;

namespace {
const fs::path data_dir = SHELLFLOW_TEST_DATA_DIR;
const fs::path panel_dir = fs::path(shellflow::source_dir) / "cases" / "panel_flutter";

fs::path temp_dir(const std::string& name) {
  auto dir = fs::temp_directory_path() / ("shellflow_test_mesh_" + name);
  fs::create_directories(dir);
  return dir;
}

std::set<std::string> names(const Mesh& m) {
  auto v = m.group_names();
  return {v.begin(), v.end()};
}
}  // namespace

TEST(GmshIo, UnitCubeOfEachOrderHasPositiveTetrahedraAndItsGroups) {
  for (int order : {1, 2, 3}) {
    const Mesh mesh = generate_mesh(data_dir / "unit_cube.geo", with_order(order), "cube");
    const auto expected = order == 1 ? ElementType::tet4 : order == 2 ? ElementType::tet10 : ElementType::tet20;
    EXPECT_EQ(mesh.cells.type, expected);
    EXPECT_EQ(mesh.dim(), 3);
    EXPECT_EQ(names(mesh), (std::set<std::string>{"bottom", "top", "sides", "cube"}));
    const auto q = summarize_quality(mesh);
    EXPECT_EQ(q.inverted, 0);
    EXPECT_GT(q.min, 0.1);
    // Volumes of the straight-sided cells add up to the cube's.
    double volume = 0;
    for (Index e = 0; e < mesh.num_cells(); ++e) {
      const auto v = mesh.cells.element(e);
      volume += tet_signed_volume(mesh.nodes[v[0]], mesh.nodes[v[1]], mesh.nodes[v[2]], mesh.nodes[v[3]]);
    }
    EXPECT_NEAR(volume, 1.0, 1e-12);
    // Boundary groups: facets of the right type, nodes on their plane.
    const auto& top = mesh.group("top");
    EXPECT_EQ(top.dim, 2);
    EXPECT_EQ(top.elements.type, facet_type(expected));
    EXPECT_GT(top.elements.size(), 0);
    for (Index n : top.nodes) EXPECT_NEAR(mesh.nodes[n].z(), 1.0, 1e-12);
    // Every cell is in the volume group.
    EXPECT_EQ(static_cast<Index>(mesh.group("cube").cells.size()), mesh.num_cells());
    // All nodes are used by some cell, and their tags are kept.
    std::vector<bool> used(mesh.nodes.size(), false);
    for (Index n : mesh.cells.connectivity) used[n] = true;
    EXPECT_TRUE(std::all_of(used.begin(), used.end(), [](bool u) { return u; }));
    EXPECT_EQ(mesh.node_tags.size(), mesh.nodes.size());
  }
}

// Gmsh sets the OpenMP thread count to its General.NumThreads (1) when it meshes; the
// solvers after the meshing must keep the process's count (they ran on one thread before).
TEST(GmshIo, MeshingKeepsTheOpenMpThreadCount) {
  const int before = omp_get_max_threads();
  omp_set_num_threads(2);
  (void)generate_mesh(data_dir / "unit_cube.geo", with_order(1), "cube");
  EXPECT_EQ(omp_get_max_threads(), 2);
  (void)physical_group_names(data_dir / "unit_cube.geo");
  EXPECT_EQ(omp_get_max_threads(), 2);
  omp_set_num_threads(before);
}

TEST(GmshIo, WrittenMshReadsBackIdentically) {
  const auto msh = temp_dir("roundtrip") / "cube.msh";
  const Mesh generated = generate_mesh(data_dir / "unit_cube.geo", with_order(3, 1.5, msh), "cube");
  const Mesh read = read_msh(msh, "cube");
  ASSERT_EQ(read.nodes.size(), generated.nodes.size());
  EXPECT_EQ(read.cells.type, ElementType::tet20);
  EXPECT_EQ(read.cells.connectivity, generated.cells.connectivity);
  for (std::size_t i = 0; i < read.nodes.size(); ++i) EXPECT_LT((read.nodes[i] - generated.nodes[i]).norm(), 1e-14);
  EXPECT_EQ(names(read), names(generated));
  EXPECT_EQ(read.group("sides").nodes, generated.group("sides").nodes);
}

TEST(GmshIo, SizeFactorScalesTheMesh) {
  const Mesh fine = generate_mesh(data_dir / "unit_cube.geo", with_order(1, 0.5), "cube");
  const Mesh coarse = generate_mesh(data_dir / "unit_cube.geo", with_order(1, 1.5), "cube");
  EXPECT_GT(fine.num_cells(), 10 * coarse.num_cells());  // ideally 27x
}

TEST(GmshIo, PanelStripIsFortyCubicTrianglesWith244Nodes) {
  const Mesh shell = generate_mesh(panel_dir / "panel_strip.geo", with_order(3), "shell");
  EXPECT_EQ(shell.cells.type, ElementType::tri10);
  EXPECT_EQ(shell.num_cells(), 40);
  EXPECT_EQ(shell.num_nodes(), 244);
  EXPECT_EQ(names(shell), (std::set<std::string>{"leading_edge", "trailing_edge", "sides", "panel"}));
  EXPECT_EQ(shell.group("leading_edge").nodes.size(), 4u);  // one cubic edge
  EXPECT_EQ(shell.group("leading_edge").elements.type, ElementType::line4);
  // Normal of every triangle is +y (into the fluid).
  for (Index e = 0; e < shell.num_cells(); ++e) {
    const auto v = shell.cells.element(e);
    const Vec3 n = (shell.nodes[v[1]] - shell.nodes[v[0]]).cross(shell.nodes[v[2]] - shell.nodes[v[0]]);
    EXPECT_GT(n.y(), 0.0) << "triangle " << e;
  }
}

TEST(GmshIo, MissingFileAndBadOrderAreInputErrors) {
  EXPECT_THROW(generate_mesh(data_dir / "no_such.geo", {}, "x"), InputError);
  EXPECT_THROW(read_msh(data_dir / "no_such.msh", "x"), InputError);
  EXPECT_THROW(generate_mesh(data_dir / "unit_cube.geo", with_order(4), "x"), InputError);
  try {
    generate_mesh(data_dir / "no_such.geo", {}, "x");
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no_such.geo"), std::string::npos);
  }
}

TEST(GmshIo, BrokenGeoFileIsAnInputErrorNamingTheFile) {
  const auto geo = temp_dir("broken") / "broken.geo";
  std::ofstream(geo) << "Point(1) = {0, 0, 0\n";  // syntax error
  try {
    generate_mesh(geo, {}, "x");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("broken.geo"), std::string::npos) << e.what();
  }
}

TEST(GmshIo, PhysicalGroupNamesWithoutMeshing) {
  const auto groups = physical_group_names(panel_dir / "fluid_slab.geo");
  const std::set<std::string> got(groups.begin(), groups.end());
  EXPECT_EQ(got, (std::set<std::string>{"inflow", "outflow", "far_field", "wall", "panel", "symmetry", "fluid"}));
}

TEST(GmshIo, MissingGroupErrorListsTheAvailableOnes) {
  const Mesh shell = generate_mesh(panel_dir / "panel_strip.geo", with_order(1), "shell");
  try {
    shell.group("leadingedge");
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("leadingedge"), std::string::npos);
    EXPECT_NE(msg.find("leading_edge"), std::string::npos);
    EXPECT_NE(msg.find("panel_strip.geo"), std::string::npos);
  }
}

// A size factor is checked against the machine before the mesh is made (issue 39): the count
// at the factor asked, extrapolated from meshes at factors 1 and 0.5, is that of the mesh made.
TEST(GmshIo, TheElementCountOfASizeFactorIsEstimatedBeforeMeshing) {
  const fs::path geo = data_dir / "unit_cube.geo";
  const MeshSizeEstimate none = estimate_mesh_size(geo, with_order(1, kSizeFactorProbedBelow));
  EXPECT_EQ(none.elements, 0.0);  // no probe at 0.25 and above
  const MeshSizeEstimate e = estimate_mesh_size(geo, with_order(1, 0.125));
  EXPECT_GT(e.exponent, 2.4);
  EXPECT_LE(e.exponent, 3.0);
  EXPECT_GT(e.limit, 1e5);
  const double made = double(generate_mesh(geo, with_order(1, 0.125), "cube").num_cells());
  EXPECT_NEAR(e.elements / made, 1.0, 0.35) << e.elements << " estimated, " << made << " made";
  // 1e-4 would be about 1e14 tetrahedra: refused with the factor, the estimate and the fix.
  MeshingOptions tiny = with_order(1, 1e-4);
  tiny.size_factor_key = "meshes.fluid.size_factor";
  try {
    check_mesh_size_of(geo, tiny);
    FAIL() << "a size factor of 1e-4 was not refused";
  } catch (const InputError& err) {
    const std::string what = err.what();
    EXPECT_NE(what.find("unit_cube.geo: meshes.fluid.size_factor 0.0001 would make about "), std::string::npos) << what;
    EXPECT_NE(what.find("raise it to "), std::string::npos) << what;
  }
  EXPECT_NO_THROW(check_mesh_size_of(geo, with_order(1, 0.125)));
}
