// ProbeSet: point probes located in a tetrahedral mesh and on a shell surface sample a linear
// field exactly (P1 interpolation), many probes share one locator per mesh, and points
// outside the mesh or off the surface are InputErrors at the probe's line.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "io_test_util.h"
#include "shellflow/core/error.h"
#include "shellflow/io/probes.h"
#include "support/box_mesh.h"

namespace shellflow::io {
namespace {

using test::TempDir;

double linear_field(const Vec3& x) { return 1.0 + 2.0 * x.x() + 3.0 * x.y() - 5.0 * x.z(); }
Vec3 linear_vector(const Vec3& x) { return {x.x(), 2.0 * x.y(), x.z() + 1.0}; }

/// Unit cube as 6 positively oriented tetrahedra (Kuhn: around the diagonal 0-7; the tests'
/// box), node i at (i & 1, (i >> 1) & 1, (i >> 2) & 1); group "bottom" = the face z = 0.
mesh::Mesh unit_cube() {
  mesh::Mesh m = support::box_mesh({1, 1, 1}, Vec3(1, 1, 1),
                                   [](const Vec3& c) { return c.z() == 0.0 ? std::string("bottom") : std::string(); });
  m.name = "fluid";
  m.source = "unit cube (test)";
  for (std::size_t i = 0; i < m.nodes.size(); ++i) m.node_tags.push_back(i + 1);
  return m;
}

/// The square [0, 2] x [0, 1] in z = 0.5 as two 3-node triangles.
mesh::Mesh flat_shell() {
  mesh::Mesh m;
  m.name = "shell";
  m.source = "square (test)";
  m.nodes = {Vec3(0, 0, 0.5), Vec3(2, 0, 0.5), Vec3(2, 1, 0.5), Vec3(0, 1, 0.5)};
  m.node_tags = {1, 2, 3, 4};
  m.cells.type = mesh::ElementType::tri3;
  m.cells.connectivity = {0, 1, 2, 0, 2, 3};
  return m;
}

Probe point_probe(const std::string& name, const std::string& mesh, const std::string& quantity, const Vec3& p,
                  ProbeComponent component, int line) {
  Probe probe;
  probe.name = name;
  probe.mesh = mesh;
  probe.quantity = quantity;
  probe.field = mesh + "." + quantity;
  probe.component = component;
  probe.location = ProbeLocation::point;
  probe.point = p;
  probe.where = {"case.yaml", line, "probes[" + std::to_string(line) + "]"};
  return probe;
}

struct Fields {
  std::vector<double> pressure, velocity, displacement;
  std::vector<FieldView> views() const {
    return {{"fluid", "pressure", 1, pressure, {}},
            {"fluid", "velocity", 3, velocity, {}},
            {"shell", "displacement", 1, displacement, {}}};
  }
};

Fields fields_of(const CaseMeshes& meshes) {
  Fields f;
  for (const Vec3& x : meshes.fluid->nodes) {
    f.pressure.push_back(linear_field(x));
    const Vec3 v = linear_vector(x);
    f.velocity.insert(f.velocity.end(), v.data(), v.data() + 3);
  }
  for (const Vec3& x : meshes.shell->nodes) f.displacement.push_back(linear_field(x));
  return f;
}

TEST(ProbeSet, ManyPointProbesInOneMeshSampleALinearFieldExactly) {
  CaseMeshes meshes;
  meshes.fluid = unit_cube();
  meshes.shell = flat_shell();
  std::vector<Probe> probes;
  std::vector<double> expected;
  // Points spread through every tetrahedron of the cube, on faces and at a vertex.
  for (int i = 0; i < 27; ++i) {
    const Vec3 p(0.05 + 0.45 * (i % 3), 0.1 + 0.4 * ((i / 3) % 3), 0.02 + 0.48 * (i / 9));
    probes.push_back(point_probe("p" + std::to_string(i), "fluid", "pressure", p, ProbeComponent::scalar, i + 1));
    expected.push_back(linear_field(p));
    probes.push_back(
        point_probe("speed" + std::to_string(i), "fluid", "velocity", p, ProbeComponent::magnitude, i + 1));
    expected.push_back(linear_vector(p).norm());
  }
  probes.push_back(point_probe("corner", "fluid", "pressure", Vec3(1, 1, 1), ProbeComponent::scalar, 60));
  expected.push_back(linear_field(Vec3(1, 1, 1)));
  probes.push_back(point_probe("vy", "fluid", "velocity", Vec3(0.3, 0.7, 0.2), ProbeComponent::y, 61));
  expected.push_back(1.4);
  for (const Vec3& p : {Vec3(0.3, 0.2, 0.5), Vec3(1.7, 0.9, 0.5), Vec3(1.0, 0.5, 0.5), Vec3(2.0, 1.0, 0.5)}) {
    probes.push_back(
        point_probe("w" + std::to_string(probes.size()), "shell", "displacement", p, ProbeComponent::scalar, 70));
    expected.push_back(linear_field(p));
  }
  Probe group;
  group.name = "p_bottom_max";
  group.mesh = "fluid";
  group.quantity = "pressure";
  group.field = "fluid.pressure";
  group.location = ProbeLocation::group;
  group.group = "bottom";
  group.reduce = ProbeReduce::max;
  probes.push_back(group);
  expected.push_back(linear_field(Vec3(1, 1, 0)));

  TempDir dir("probes");
  ProbeSet set(probes, meshes, dir / "probes.csv");
  ASSERT_EQ(set.size(), probes.size());
  const Fields f = fields_of(meshes);
  const auto views = f.views();
  const std::vector<double> values = set.sample(views);
  ASSERT_EQ(values.size(), expected.size());
  double worst = 0.0;
  for (std::size_t k = 0; k < values.size(); ++k) {
    EXPECT_NEAR(values[k], expected[k], 1e-12) << probes[k].name;
    worst = std::max(worst, std::abs(values[k] - expected[k]));
  }
  std::printf("%zu probes: max interpolation error %.2e\n", values.size(), worst);
}

TEST(ProbeSet, TheSameStateRecordedTwiceIsOneRow) {
  // A run whose solver fails records its last valid state again before reporting the error.
  CaseMeshes meshes;
  meshes.fluid = unit_cube();
  std::vector<Probe> probes{point_probe("p", "fluid", "pressure", Vec3(0.3, 0.2, 0.5), ProbeComponent::scalar, 1)};
  TempDir dir("probes_repeated");
  {
    ProbeSet set(probes, meshes, dir / "probes.csv");
    const Fields f = fields_of(meshes);
    const auto views = f.views();
    for (const double t : {0.0, 0.0, 0.5, 1.0, 1.0, 0.5}) set.record(t, views);
  }
  std::ifstream in(dir / "probes.csv");
  std::vector<std::string> times;
  for (std::string line; std::getline(in, line);) times.push_back(line.substr(0, line.find(',')));
  EXPECT_EQ(times, (std::vector<std::string>{"time", "0", "0.5", "1", "0.5"}));
}

TEST(ProbeSet, PointOutsideTheMeshAfterValidProbesNamesTheProbeLine) {
  CaseMeshes meshes;
  meshes.fluid = unit_cube();
  meshes.shell = flat_shell();
  const std::vector<Probe> probes = {
      point_probe("a", "fluid", "pressure", Vec3(0.5, 0.5, 0.5), ProbeComponent::scalar, 3),
      point_probe("b", "fluid", "pressure", Vec3(0.2, 0.1, 0.9), ProbeComponent::scalar, 4),
      point_probe("c", "fluid", "pressure", Vec3(1.5, 0.5, 0.5), ProbeComponent::scalar, 5)};
  TempDir dir("probes-outside");
  try {
    ProbeSet set(probes, meshes, dir / "probes.csv");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("case.yaml:5"), std::string::npos) << message;
    EXPECT_NE(message.find("point (1.5, 0.5, 0.5) lies outside the fluid mesh; move it into the domain"),
              std::string::npos)
        << message;
  }
}

TEST(ProbeSet, PointOffTheShellSurfaceAfterValidProbesNamesTheProbeLine) {
  CaseMeshes meshes;
  meshes.fluid = unit_cube();
  meshes.shell = flat_shell();
  const std::vector<Probe> probes = {
      point_probe("a", "shell", "displacement", Vec3(0.5, 0.5, 0.5), ProbeComponent::scalar, 3),
      point_probe("b", "shell", "displacement", Vec3(0.5, 0.5, 0.6), ProbeComponent::scalar, 8)};
  TempDir dir("probes-off-surface");
  try {
    ProbeSet set(probes, meshes, dir / "probes.csv");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("case.yaml:8"), std::string::npos) << message;
    EXPECT_NE(message.find("is 0.1 m away from the shell surface; put it on the surface"), std::string::npos)
        << message;
  }
}

}  // namespace
}  // namespace shellflow::io
