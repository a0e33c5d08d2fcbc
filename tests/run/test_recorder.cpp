// The recorder: frame 0 written once (the run kind's outputs from the solvers' state, the
// initial output for the other meshes), and probes sampled at their located nodes through
// lazy views equal to sampling the whole fields.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "run_test_util.h"
#include "shellflow/fluid/fluid_model.h"
#include "shellflow/io/case.h"
#include "shellflow/run/recorder.h"

namespace shellflow::run {
namespace {

using test::cube_mesh;
using test::read_file;
using test::TempDir;

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

/// A run kind's output of the fluid mesh that counts its frames.
class CountingOutput final : public MeshOutput {
 public:
  CountingOutput(const mesh::Mesh& m, const std::filesystem::path& outdir)
      : MeshOutput(m, outdir, io::OutputMode::create), values_(m.nodes.size(), 7.0) {}
  std::vector<io::FieldView> views() const override { return {{"fluid", "pressure", 1, values_, {}}}; }
  void write(long step, double t) override {
    ++writes;
    write_frame(step, t, {{"pressure", 1, values_}});
  }
  int writes = 0;

 private:
  std::vector<double> values_;
};

io::Probe node_probe(std::string name, std::string mesh, std::string quantity, Index node) {
  io::Probe p;
  p.name = std::move(name);
  p.mesh = std::move(mesh);
  p.quantity = std::move(quantity);
  p.field = p.mesh + "." + p.quantity;
  p.location = io::ProbeLocation::node;
  p.node = node;
  return p;
}

TEST(Recorder, FrameZeroOnceInitialOutputsOnlyForTheOtherMeshes) {
  TempDir dir;
  io::CaseMeshes meshes;
  meshes.fluid = cube_mesh("fluid");
  meshes.space = cube_mesh("space");
  io::Case c;
  c.probes = {node_probe("p", "fluid", "pressure", 4), node_probe("s", "space", "displacement", 4)};
  c.probes[1].component = io::ProbeComponent::z;
  Recorder recorder(c, meshes, dir.path(), io::OutputMode::create);
  CountingOutput fluid(*meshes.fluid, dir.path());
  recorder.add(fluid);
  recorder.record(0, 0.0, Record::probes_and_fields);
  recorder.record(1, 0.5, Record::probes);
  recorder.record(2, 1.0, Record::probes_and_fields);
  EXPECT_EQ(fluid.writes, 2);
  // The space mesh keeps its initial state: its frame 0, once, and no later frame.
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "space_000000.vtu"));
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "space_000002.vtu"));
  EXPECT_EQ(count(read_file(dir.path() / "space.pvd"), "<DataSet"), 1u);
  EXPECT_EQ(count(read_file(dir.path() / "fluid.pvd"), "<DataSet"), 2u);
  // The run kind's view replaces the initial one; the space mesh's initial view is zero.
  const std::string csv = read_file(dir.path() / "probes.csv");
  EXPECT_EQ(count(csv, "\n"), 4u) << csv;  // header + 3 rows
  EXPECT_NE(csv.find("0.5,7,0"), std::string::npos) << csv;
}

// A restarted run's recorder leaves the frames of the meshes it does not move as the first
// invocation wrote them (their .pvd is not started again).
TEST(Recorder, ARestartKeepsTheInitialFrames) {
  TempDir dir;
  io::CaseMeshes meshes;
  meshes.fluid = cube_mesh("fluid");
  meshes.space = cube_mesh("space");
  const io::Case c;
  {
    Recorder first(c, meshes, dir.path(), io::OutputMode::create);
    first.record(0, 0.0, Record::probes_and_fields);
  }
  const std::string before = read_file(dir.path() / "space.pvd");
  ASSERT_EQ(count(before, "<DataSet"), 1u);
  Recorder restarted(c, meshes, dir.path(), io::OutputMode::resume);
  restarted.record(5, 1.0, Record::fields);  // probes.csv resumes only through RunControl::restore
  EXPECT_EQ(read_file(dir.path() / "space.pvd"), before);
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "space_000005.vtu"));
}

/// A smooth vector field on the cube.
Vec3 field(const Vec3& x) { return {std::sin(x.x()) + x.y(), x.z() * x.z() - 0.3, x.x() * x.y() * x.z() + 1.0}; }

TEST(ProbeSampler, LazyViewsSampleLikeWholeFields) {
  io::CaseMeshes meshes;
  meshes.fluid = cube_mesh("fluid");
  const mesh::Mesh& m = *meshes.fluid;
  std::vector<io::Probe> probes;
  for (const auto component : {io::ProbeComponent::x, io::ProbeComponent::z, io::ProbeComponent::magnitude}) {
    io::Probe point = node_probe("point" + std::to_string(probes.size()), "fluid", "velocity", 0);
    point.location = io::ProbeLocation::point;
    point.point = Vec3(0.3, 1.7, 0.45);
    point.component = component;
    io::Probe group = node_probe("group" + std::to_string(probes.size()), "fluid", "velocity", 0);
    group.location = io::ProbeLocation::group;
    group.group = "bottom";
    group.component = component;
    for (const auto reduce : {io::ProbeReduce::mean, io::ProbeReduce::min, io::ProbeReduce::max}) {
      group.reduce = reduce;
      group.name += "r";
      probes.push_back(group);
    }
    probes.push_back(point);
    probes.push_back(node_probe("node" + std::to_string(probes.size()), "fluid", "velocity", 13));
    probes.back().component = component;
  }
  TempDir dir;
  const io::ProbeSet set(probes, meshes, dir.path() / "probes.csv");
  std::vector<double> whole;
  for (const Vec3& x : m.nodes) {
    const Vec3 v = field(x);
    whole.insert(whole.end(), v.data(), v.data() + 3);
  }
  int calls = 0;
  const std::vector<io::FieldView> eager = {{"fluid", "velocity", 3, whole, {}}};
  const std::vector<io::FieldView> lazy = {{"fluid", "velocity", 3, {}, [&](Index node, double* out) {
                                              ++calls;
                                              const Vec3 v = field(m.nodes[std::size_t(node)]);
                                              std::copy(v.data(), v.data() + 3, out);
                                            }}};
  const std::vector<double> a = set.sample(eager), b = set.sample(lazy);
  ASSERT_EQ(a.size(), probes.size());
  for (std::size_t k = 0; k < a.size(); ++k) EXPECT_EQ(a[k], b[k]) << probes[k].name;
  // Only the probes' nodes are evaluated: 4 per point probe, 1 per node probe, 9 per group.
  EXPECT_EQ(calls, 3 * (4 + 1 + 3 * 9));
}

/// The flow's lazy probe views against the whole fields computed node by node from the
/// model's state, as the frames were before (FluidWriter).
TEST(FluidOutput, LazyViewsEqualTheWholeFields) {
  mesh::Mesh mesh = cube_mesh("fluid");
  mesh.groups.clear();  // no boundary conditions needed: the state is set, not stepped
  fluid::FluidModel model(std::move(mesh), fluid::FluidOptions{}, {});
  model.set_state([](const Vec3& x) {
    return fluid::Primitive{1.0 + 0.1 * x.x(), Vec3(300.0 + x.y(), -2.0 * x.z(), 5.0), 1e5 * (1.0 + 0.01 * x.y())};
  });
  const mesh::Mesh case_mesh = cube_mesh("fluid");
  std::vector<Index> identity(case_mesh.nodes.size());
  for (std::size_t i = 0; i < identity.size(); ++i) identity[i] = Index(i);
  TempDir dir;
  const FluidOutput output(case_mesh, identity, model, dir.path(), io::OutputMode::create);
  const auto& gas = model.options().gas;
  for (const io::FieldView& view : output.views()) {
    ASSERT_TRUE(view.at) << view.quantity;
    for (Index k = 0; k < Index(case_mesh.nodes.size()); ++k) {
      const fluid::Primitive p = model.primitive(k);
      const auto q = model.state().get(k);
      std::vector<double> expected;
      if (view.quantity == "density") expected = {p.rho};
      if (view.quantity == "pressure") expected = {p.pressure};
      if (view.quantity == "temperature") expected = {gas.temperature(p.rho, p.pressure)};
      if (view.quantity == "mach") expected = {p.velocity.norm() / gas.sound_speed(p.rho, p.pressure)};
      if (view.quantity == "energy") expected = {q.energy};
      if (view.quantity == "velocity") expected = {p.velocity.x(), p.velocity.y(), p.velocity.z()};
      if (view.quantity == "momentum") expected = {q.momentum.x(), q.momentum.y(), q.momentum.z()};
      if (view.quantity == "mesh_velocity") expected = {0.0, 0.0, 0.0};
      ASSERT_EQ(expected.size(), std::size_t(view.components)) << view.quantity;
      double got[9];
      view.at(k, got);
      for (int i = 0; i < view.components; ++i) EXPECT_EQ(got[i], expected[std::size_t(i)]) << view.quantity;
    }
  }
}

}  // namespace
}  // namespace shellflow::run
