// ALE consistency on oscillating meshes: the stationary contact (fluid-references.md c2,
// only the mesh-velocity terms act) and Sod on a deforming mesh (a3).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "exact_riemann.h"
#include "fluid_test_util.h"
#include "symmetric_tube.h"

using namespace shellflow;
using namespace shellflow::fluid;

namespace {

constexpr double pi = std::numbers::pi;

std::vector<BoundaryCondition> tube_conditions() {
  return {{"left", BoundaryKind::slip_wall, {}, {}},
          {"right", BoundaryKind::slip_wall, {}, {}},
          {"sides", BoundaryKind::symmetry, {}, {}}};
}

double rho0(double x) { return 1.0 + 0.5 * std::exp(-std::pow((x - 0.5) / 0.1, 2)); }

struct ContactError {
  double l1, max;
};

ContactError stationary_contact(int nx, TgVelocity tg_velocity, bool c2 = true, double cfl = 0.5) {
  FluidOptions o;
  o.tg_velocity = tg_velocity;
  o.moving_mesh_correction = c2;
  FluidModel model(test_support::case_mesh("tube_nx" + std::to_string(nx) + ".geo"), o, tube_conditions());
  model.set_state([](const Vec3& x) { return Primitive{rho0(x.x()), Vec3::Zero(), 1.0}; });
  test_support::run_until_moving(model, 1.0, cfl, [](const Vec3& X, double t) {
    return Vec3(X.x() + 0.05 * std::sin(pi * X.x()) * std::sin(2 * pi * t / 0.5), X.y(), X.z());
  });
  ContactError err{0, 0};
  const auto n = model.mesh().num_nodes();
  for (Index a = 0; a < n; ++a) {
    const double e = std::abs(model.primitive(a).rho - rho0(model.positions()[std::size_t(a)].x()));
    err.l1 += e / n;
    err.max = std::max(err.max, e);
  }
  return err;
}

}  // namespace

TEST(MovingMesh, StationaryContactOnAnOscillatingMeshConvergesAtSecondOrder) {
  const int resolutions[] = {100, 200, 400};
  std::vector<ContactError> errors;
  for (const int nx : resolutions) {
    errors.push_back(stationary_contact(nx, TgVelocity::relative));
    std::printf("stationary contact Nx=%d: mean |error| %.3e, max |error|/0.5 %.3e\n", nx, errors.back().l1,
                errors.back().max / 0.5);
  }
  for (std::size_t i = 1; i < errors.size(); ++i) {
    const double order = std::log2(errors[i - 1].max / errors[i].max);
    std::printf("observed max-norm order %d -> %d: %.3f (mean-norm %.3f)\n", resolutions[i - 1], resolutions[i], order,
                std::log2(errors[i - 1].l1 / errors[i].l1));
    EXPECT_GE(order, 1.5);
  }
  EXPECT_LE(errors[1].max / 0.5, 5e-3);  // Nx = 200
}

TEST(MovingMesh, SodOnADeformingMeshIsAsAccurateAsOnAFixedOne) {
  using test_support::ExactRiemann;
  using test_support::State1d;
  const State1d left{1.0, 0.0, 1.0}, right{0.125, 0.0, 0.1};
  const ExactRiemann exact(left, right);
  for (const int nx : {100, 200}) {
    double l1[2] = {0, 0};
    for (const bool moving : {false, true}) {
      FluidOptions o;
      o.q_dif = 1.0;
      FluidModel model(test_support::case_mesh("tube_nx" + std::to_string(nx) + ".geo"), o, tube_conditions());
      model.set_state([&](const Vec3& x) {
        const State1d s = x.x() < 0.5 - 1e-12 ? left : x.x() > 0.5 + 1e-12 ? right : State1d{0.5625, 0.0, 0.55};
        return Primitive{s.rho, Vec3::Zero(), s.p};
      });
      test_support::run_until_moving(model, 0.2, 0.5, [&](const Vec3& X, double t) {
        const double amplitude = moving ? 0.01 : 0.0;
        return Vec3(X.x() + amplitude * std::sin(pi * X.x()) * std::sin(2 * pi * t / 0.1), X.y(), X.z());
      });
      // Nodes are back at X at t = 0.2 (up to round-off); L1 over nodes, one value per x.
      const auto n = model.mesh().num_nodes();
      for (Index a = 0; a < n; ++a) {
        const double x = model.positions()[std::size_t(a)].x();
        l1[moving] += std::abs(model.primitive(a).rho - exact.sample((x - 0.5) / 0.2).rho) / n;
      }
    }
    std::printf("Sod Nx=%d: L1(rho) fixed %.5f, deforming %.5f (ratio %.3f)\n", nx, l1[0], l1[1], l1[1] / l1[0]);
    EXPECT_LE(l1[1], 1.25 * l1[0]) << "Nx = " << nx;
  }
}

TEST(MovingMesh, PaperVelocityOrMissingC2CorrectionIsOnlyFirstOrder) {
  // The checks above can fail: the paper's literal fluid velocity in the dt^2/2 term, or
  // dropping the moving-mesh correction C2, lose the second order (fluid.md 3.2, 4.2).
  const auto fluid_200 = stationary_contact(200, TgVelocity::fluid);
  const auto fluid_400 = stationary_contact(400, TgVelocity::fluid);
  const auto no_c2_200 = stationary_contact(200, TgVelocity::relative, false);
  const auto no_c2_400 = stationary_contact(400, TgVelocity::relative, false);
  const double order_fluid = std::log2(fluid_200.max / fluid_400.max);
  const double order_no_c2 = std::log2(no_c2_200.max / no_c2_400.max);
  std::printf("order 200 -> 400: tg_velocity = fluid %.3f, without C2 %.3f\n", order_fluid, order_no_c2);
  EXPECT_LT(order_fluid, 1.2);
  EXPECT_LT(order_no_c2, 1.4);
}

namespace {

/// Piston (fluid-references.md d1): the face x = 0 is a slip wall moving at V, reached by
/// a linear ramp over 0 <= t <= 0.02; the mesh follows x = X + s(t) (1 - X). Returns the
/// piston-face pressure averaged over 0.3 <= t <= 0.5.
double piston_pressure(double V, int nx, int consistent_mass_iterations = 0, double cfl = 0.5) {
  const double ramp = 0.02;
  auto velocity = [=](double t) { return V * std::min(t / ramp, 1.0); };
  auto position = [=](double t) { return t < ramp ? 0.5 * V * t * t / ramp : V * (0.5 * ramp + (t - ramp)); };
  FluidOptions o;
  o.q_dif = 1.0;
  o.consistent_mass_iterations = consistent_mass_iterations;
  FluidModel model(
      test_support::case_mesh("tube_nx" + std::to_string(nx) + ".geo"), o,
      {{"left", BoundaryKind::slip_wall, {}, [&](Index, const Vec3&, double t) { return Vec3(velocity(t), 0.0, 0.0); }},
       {"right", BoundaryKind::slip_wall, {}, {}},
       {"sides", BoundaryKind::symmetry, {}, {}}});
  model.set_state([](const Vec3&) { return Primitive{1.4, Vec3::Zero(), 1.0}; });
  const auto& piston_nodes = model.mesh().group("left").nodes;
  const std::vector<Vec3> X(model.positions().begin(), model.positions().end());
  std::vector<Vec3> x(X.size());
  double integral = 0.0, duration = 0.0;
  const double t_end = 0.5;
  while (model.time() < t_end * (1 - 1e-14)) {
    const double dt = std::min(model.stable_dt(cfl), t_end - model.time());
    const double t_next = model.time() + dt;
    for (std::size_t a = 0; a < X.size(); ++a)
      x[a] = Vec3(X[a].x() + position(t_next) * (1 - X[a].x()), X[a].y(), X[a].z());
    model.step(dt, x);
    if (model.time() > 0.3) {
      double p = 0.0;
      for (const Index a : piston_nodes) p += model.primitive(a).pressure;
      integral += dt * p / double(piston_nodes.size());
      duration += dt;
    }
  }
  return integral / duration;
}

}  // namespace

TEST(MovingMesh, PistonFacePressureMatchesTheExactWaveSolution) {
  struct Case {
    double V, p_exact;
  };
  for (const Case c :
       {Case{0.01, 1.01408425}, Case{0.1, 1.14865177}, Case{-0.01, 0.98608372}, Case{-0.1, 0.86812553}}) {
    const double p = piston_pressure(c.V, 100);
    std::printf("piston V=%+.2f: p = %.6f, exact %.6f, error %+.4f%%\n", c.V, p, c.p_exact, 100 * (p / c.p_exact - 1));
    EXPECT_NEAR(p / c.p_exact, 1.0, 0.005) << "V = " << c.V;
  }
}

TEST(MovingMesh, PistonWithConsistentMassMatchesTooAtCfl03) {
  for (const double V : {0.1, -0.1}) {
    const double p = piston_pressure(V, 100, 3, 0.3);
    const double exact = V > 0 ? 1.14865177 : 0.86812553;
    std::printf("piston (consistent mass) V=%+.2f: p = %.6f, error %+.4f%%\n", V, p, 100 * (p / exact - 1));
    EXPECT_NEAR(p / exact, 1.0, 0.005);
  }
}

namespace {

/// c3: rho = 1 + 0.2 sin(2 pi (x - 2 t)), u = 2, p = 1 (supersonic), mesh motion as c2,
/// t = 1; inflow prescribes the exact state, outflow is natural (C3 term). Max error.
/// `symmetric`: the tube with mirrored columns (symmetric_tube.h); the extruded tube of
/// cases/fluid gives first order here (lopsided lumped mass, see symmetric_tube.h).
double entropy_wave_error(int nx, double amplitude = 0.05, int mass_iterations = 0, double* x_worst = nullptr,
                          bool symmetric = true) {
  auto exact = [](const Vec3& x, double t) {
    return Primitive{1.0 + 0.2 * std::sin(2 * pi * (x.x() - 2 * t)), Vec3(2.0, 0.0, 0.0), 1.0};
  };
  FluidOptions o;
  o.consistent_mass_iterations = mass_iterations;
  FluidModel model(symmetric ? test_support::symmetric_tube(nx, 0.02)
                             : test_support::case_mesh("tube_nx" + std::to_string(nx) + ".geo"),
                   o,
                   {{"left", BoundaryKind::supersonic_inflow, {}, {}, exact},
                    {"right", BoundaryKind::supersonic_outflow, {}, {}, {}},
                    {"sides", BoundaryKind::symmetry, {}, {}, {}}});
  model.set_state([&](const Vec3& x) { return exact(x, 0.0); });
  test_support::run_until_moving(model, 1.0, mass_iterations ? 0.3 : 0.5, [&](const Vec3& X, double t) {
    return Vec3(X.x() + amplitude * std::sin(pi * X.x()) * std::sin(2 * pi * t / 0.5), X.y(), X.z());
  });
  double err = 0.0;
  for (Index a = 0; a < model.mesh().num_nodes(); ++a) {
    const double e = std::abs(model.primitive(a).rho - exact(model.positions()[std::size_t(a)], model.time()).rho);
    if (e > err && x_worst) *x_worst = model.positions()[std::size_t(a)].x();
    err = std::max(err, e);
  }
  return err;
}

}  // namespace

TEST(MovingMesh, EntropyWaveOnAMovingMeshConvergesAtSecondOrder) {
  const int resolutions[] = {50, 100, 200};
  std::vector<double> errors;
  for (const int nx : resolutions) {
    errors.push_back(entropy_wave_error(nx));
    std::printf("entropy wave Nx=%d: max |rho error| %.3e\n", nx, errors.back());
  }
  for (std::size_t i = 1; i < errors.size(); ++i) {
    const double order = std::log2(errors[i - 1] / errors[i]);
    std::printf("entropy wave order %d -> %d: %.3f\n", resolutions[i - 1], resolutions[i], order);
    EXPECT_GE(order, 1.7);
  }
}

TEST(MovingMesh, EntropyWaveWithConsistentMassConvergesAtSecondOrder) {
  const int resolutions[] = {50, 100, 200};
  std::vector<double> errors;
  for (const int nx : resolutions) {
    errors.push_back(entropy_wave_error(nx, 0.05, 3));
    std::printf("entropy wave (consistent mass) Nx=%d: max |rho error| %.3e\n", nx, errors.back());
  }
  for (std::size_t i = 1; i < errors.size(); ++i) {
    const double order = std::log2(errors[i - 1] / errors[i]);
    std::printf("entropy wave (consistent mass) order %d -> %d: %.3f\n", resolutions[i - 1], resolutions[i], order);
    EXPECT_GE(order, 1.7);
  }
}
