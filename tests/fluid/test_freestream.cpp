// Free-stream preservation on deforming meshes (fluid-references.md c1): a uniform
// supersonic flow stays exactly uniform whatever the mesh motion.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "fluid_test_util.h"

using namespace shellflow;
using namespace shellflow::fluid;

namespace {

constexpr double gamma_air = 1.4;
const double angle = 10.0 * std::numbers::pi / 180.0;
const Primitive free_stream{1.0, 2.3 * Vec3(std::cos(angle), std::sin(angle), 0.0), 1.0 / gamma_air};

double max_relative_deviation(const FluidModel& model) {
  const Conservative q = to_conservative(model.options().gas, free_stream);
  const double scale = std::sqrt(q.rho * q.rho + q.momentum.squaredNorm() + q.energy * q.energy);
  double worst = 0.0;
  for (Index a = 0; a < model.mesh().num_nodes(); ++a) {
    const Conservative s = model.state().get(a);
    const double d = std::sqrt(std::pow(s.rho - q.rho, 2) + (s.momentum - q.momentum).squaredNorm() +
                               std::pow(s.energy - q.energy, 2));
    worst = std::max(worst, d / scale);
  }
  return worst;
}

FluidModel cube_model(BoundaryKind kind, int consistent_mass_iterations = 0) {
  FluidOptions o;
  o.consistent_mass_iterations = consistent_mass_iterations;
  o.gas.gamma = gamma_air;
  o.q_dif = 1.0;  // shock capturing on
  FluidModel model(test_support::case_mesh("unit_cube.geo"), o, {{"boundary", kind, free_stream, {}}});
  model.set_state([](const Vec3&) { return free_stream; });
  return model;
}

// x = X + A sin(2 pi t / T) sin(pi X) sin(pi Y) sin(pi Z) (1, 0.8, 0.6).
Vec3 smooth_motion(const Vec3& X, double t) {
  const double A = 0.05, T = 0.386, pi = std::numbers::pi;
  return X + A * std::sin(2 * pi * t / T) * std::sin(pi * X.x()) * std::sin(pi * X.y()) * std::sin(pi * X.z()) *
                 Vec3(1.0, 0.8, 0.6);
}

}  // namespace

TEST(FreeStream, IsPreservedExactlyOnASmoothlyDeformingMesh) {
  auto model = cube_model(BoundaryKind::supersonic_inflow);
  const std::vector<Vec3> X = model.mesh().nodes;
  std::vector<Vec3> x(X.size());
  double worst = 0.0;
  for (int n = 0; n < 1000; ++n) {
    const double dt = model.stable_dt(0.5);
    for (std::size_t a = 0; a < X.size(); ++a) x[a] = smooth_motion(X[a], model.time() + dt);
    model.step(dt, x);
    worst = std::max(worst, max_relative_deviation(model));
  }
  double max_w = 0;
  for (const auto& w : model.mesh_velocity()) max_w = std::max(max_w, w.norm());
  std::printf("smooth motion: t = %.4f, max |w| at the end %.3f, max deviation %.3e\n", model.time(), max_w, worst);
  EXPECT_LE(worst, 1e-12);
}

TEST(FreeStream, IsPreservedExactlyWithRandomMeshVelocities) {
  auto model = cube_model(BoundaryKind::supersonic_inflow);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> jitter(-0.02, 0.02), speed(-1.15, 1.15);
  std::vector<Vec3> x = model.mesh().nodes;
  for (auto& p : x)  // a distorted (but fixed) interior
    if (p.minCoeff() > 1e-9 && p.maxCoeff() < 1 - 1e-9) p += Vec3(jitter(rng), jitter(rng), jitter(rng));
  std::vector<Vec3> w(x.size());
  double worst = 0.0;
  for (int n = 0; n < 1000; ++n) {
    for (auto& v : w) v = Vec3(speed(rng), speed(rng), speed(rng));
    const double dt = model.stable_dt(0.5);
    model.step(dt, x, w);
    worst = std::max(worst, max_relative_deviation(model));
  }
  std::printf("random w: max deviation %.3e after %ld steps\n", worst, model.steps());
  EXPECT_LE(worst, 1e-12);
}

TEST(FreeStream, IsPreservedByTheCharacteristicFarField) {
  auto model = cube_model(BoundaryKind::far_field);
  const std::vector<Vec3> X = model.mesh().nodes;
  std::vector<Vec3> x(X.size());
  double worst = 0.0;
  for (int n = 0; n < 300; ++n) {
    const double dt = model.stable_dt(0.5);
    for (std::size_t a = 0; a < X.size(); ++a) x[a] = smooth_motion(X[a], model.time() + dt);
    model.step(dt, x);
    worst = std::max(worst, max_relative_deviation(model));
  }
  std::printf("far field: max deviation %.3e\n", worst);
  EXPECT_LE(worst, 1e-12);
}

TEST(FreeStream, IsPreservedExactlyWithConsistentMass) {
  auto model = cube_model(BoundaryKind::supersonic_inflow, 3);
  const std::vector<Vec3> X = model.mesh().nodes;
  std::vector<Vec3> x(X.size());
  double worst = 0.0;
  for (int n = 0; n < 300; ++n) {
    const double dt = model.stable_dt(0.3);
    for (std::size_t a = 0; a < X.size(); ++a) x[a] = smooth_motion(X[a], model.time() + dt);
    model.step(dt, x);
    worst = std::max(worst, max_relative_deviation(model));
  }
  std::printf("consistent mass: max deviation %.3e\n", worst);
  EXPECT_LE(worst, 1e-12);
}
