// The mesh cache of io::load_case_meshes (docs/output.md): `<key>.msh.cache` in the output
// folder gives back exactly the mesh Gmsh generates, and only while its inputs are unchanged.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "io_test_util.h"
#include "shellflow/io/case.h"
#include "shellflow/io/case_meshes.h"
#include "shellflow/io/checkpoint.h"

namespace shellflow::io {
namespace {

using test::LogCapture;
namespace fs = std::filesystem;

void write_text(const fs::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out << text;
}

/// A case folder: case.yaml meshing tube.geo (an Include of the verification tube) with `nx`
/// columns.
void write_case(const fs::path& dir, int nx) {
  fs::copy_file(fs::path(SHELLFLOW_SOURCE_DIR) / "cases/fluid/tube.geo", dir / "tube.geo",
                fs::copy_options::skip_existing);
  write_text(dir / "wrapper.geo", "Nx = " + std::to_string(nx) + ";\nInclude \"tube.geo\";\n");
  write_text(dir / "case.yaml", "name: cache\nmeshes:\n  fluid: { geo: wrapper.geo, order: 1 }\n");
}

mesh::Mesh load(const fs::path& case_dir, const std::optional<fs::path>& msh_dir,
                const std::optional<fs::path>& cache_dir = std::nullopt) {
  const Case c = read_case(case_dir / "case.yaml");
  return *load_case_meshes(c, msh_dir, cache_dir).fluid;
}

void expect_same_blocks(const mesh::ElementBlock& a, const mesh::ElementBlock& b) {
  EXPECT_EQ(a.type, b.type);
  EXPECT_EQ(a.connectivity, b.connectivity);
}

/// Nodes bit for bit, node tags, cells, physical groups.
void expect_identical(const mesh::Mesh& a, const mesh::Mesh& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.source, b.source);
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  EXPECT_EQ(std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(Vec3)), 0);
  EXPECT_EQ(a.node_tags, b.node_tags);
  expect_same_blocks(a.cells, b.cells);
  ASSERT_EQ(a.groups.size(), b.groups.size());
  for (std::size_t g = 0; g < a.groups.size(); ++g) {
    SCOPED_TRACE(a.groups[g].name);
    EXPECT_EQ(a.groups[g].name, b.groups[g].name);
    EXPECT_EQ(a.groups[g].dim, b.groups[g].dim);
    EXPECT_EQ(a.groups[g].tag, b.groups[g].tag);
    expect_same_blocks(a.groups[g].elements, b.groups[g].elements);
    EXPECT_EQ(a.groups[g].nodes, b.groups[g].nodes);
    EXPECT_EQ(a.groups[g].cells, b.groups[g].cells);
  }
}

TEST(MeshCache, CachedMeshIsTheGeneratedOneBitForBit) {
  const test::TempDir dir("mesh-cache");
  write_case(dir.path(), 7);
  const fs::path out = dir / "out";
  fs::create_directories(out);
  LogCapture log;
  const mesh::Mesh fresh = load(dir.path(), std::nullopt);  // no cache involved
  const mesh::Mesh first = load(dir.path(), out);
  EXPECT_NE(log.text().find("fluid mesh: meshing wrapper.geo (no cache)"), std::string::npos) << log.text();
  ASSERT_TRUE(fs::is_regular_file(out / "fluid.msh"));
  ASSERT_TRUE(fs::is_regular_file(out / "fluid.msh.cache"));
  log.clear();
  const mesh::Mesh cached = load(dir.path(), out);
  EXPECT_NE(log.text().find("fluid mesh: from the cache"), std::string::npos) << log.text();
  EXPECT_EQ(log.text().find("meshing"), std::string::npos) << log.text();
  EXPECT_FALSE(fresh.groups.empty());
  expect_identical(fresh, first);
  expect_identical(fresh, cached);
  EXPECT_EQ(mesh_digest(fresh), mesh_digest(cached));

  // Read-only use (a restart): the cache is read, nothing is written.
  const auto written = fs::last_write_time(out / "fluid.msh.cache");
  log.clear();
  expect_identical(fresh, load(dir.path(), std::nullopt, out));
  EXPECT_NE(log.text().find("fluid mesh: from the cache"), std::string::npos) << log.text();
  EXPECT_EQ(fs::last_write_time(out / "fluid.msh.cache"), written);
}

TEST(MeshCache, ChangedGeoOrIncludedFileInvalidatesTheCache) {
  const test::TempDir dir("mesh-cache-stale");
  write_case(dir.path(), 7);
  const fs::path out = dir / "out";
  fs::create_directories(out);
  const mesh::Mesh seven = load(dir.path(), out);

  LogCapture log;
  write_case(dir.path(), 9);  // the .geo itself
  const mesh::Mesh nine = load(dir.path(), out);
  EXPECT_NE(log.text().find("fluid mesh: meshing wrapper.geo (stale"), std::string::npos) << log.text();
  EXPECT_EQ(nine.num_cells(), seven.num_cells() / 7 * 9);
  expect_identical(load(dir.path(), std::nullopt), nine);

  // A file the .geo includes: the tube 0.03 wide instead of 0.02.
  std::ifstream in(dir / "tube.geo");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto at = text.find("width = 0.02;");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 13, "width = 0.03;");
  write_text(dir / "tube.geo", text);
  log.clear();
  const mesh::Mesh wider = load(dir.path(), out);
  EXPECT_NE(log.text().find("(stale"), std::string::npos) << log.text();
  expect_identical(load(dir.path(), std::nullopt), wider);
  EXPECT_NE(mesh_digest(wider), mesh_digest(nine));

  // The case's meshing options: order 2.
  write_text(dir / "case.yaml", "name: cache\nmeshes:\n  fluid: { geo: wrapper.geo, order: 2 }\n");
  log.clear();
  EXPECT_THROW(load(dir.path(), out), InputError);  // the fluid mesh must be of order 1: not from a cache
  EXPECT_NE(log.text().find("(stale"), std::string::npos) << log.text();
}

TEST(MeshCache, DamagedOrForeignCacheIsIgnored) {
  const test::TempDir dir("mesh-cache-damaged");
  write_case(dir.path(), 5);
  const fs::path out = dir / "out";
  fs::create_directories(out);
  const mesh::Mesh fresh = load(dir.path(), out);
  const fs::path cache = out / "fluid.msh.cache";
  std::ifstream in(cache, std::ios::binary);
  const std::string good((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();

  LogCapture log;
  std::string flipped = good;
  flipped[flipped.size() / 2] = static_cast<char>(flipped[flipped.size() / 2] ^ 0x10);
  for (const std::string& bad : {good.substr(0, good.size() - 9), flipped, std::string("garbage"), std::string()}) {
    write_text(cache, bad);
    log.clear();
    expect_identical(fresh, load(dir.path(), out));
    EXPECT_NE(log.text().find("fluid mesh: meshing wrapper.geo"), std::string::npos) << log.text();
  }
  // Rewritten by the last run: good again.
  log.clear();
  expect_identical(fresh, load(dir.path(), out));
  EXPECT_NE(log.text().find("from the cache"), std::string::npos) << log.text();

  // A .msh that is not the one the cache was written with.
  write_text(out / "fluid.msh", "$MeshFormat\n");
  log.clear();
  expect_identical(fresh, load(dir.path(), out));
  EXPECT_NE(log.text().find("not the one written with the cache"), std::string::npos) << log.text();
}

}  // namespace
}  // namespace shellflow::io
