// Boundary conditions: wall constraints at faces, edges and corners, moving walls, input
// errors, positivity and inversion errors that leave the last valid state.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "fluid_test_util.h"
#include "shellflow/core/error.h"

using namespace shellflow;
using namespace shellflow::fluid;

namespace {

int count_on_boundary(const Vec3& x) {
  int n = 0;
  for (int j = 0; j < 3; ++j) n += (x[j] < 1e-9 || x[j] > 1 - 1e-9);
  return n;
}

/// The unit cube of slip walls, imposed strongly (projected at the nodes) unless `weak`.
FluidModel wall_cube(WallVelocity wall_velocity = {}, bool weak = false) {
  FluidOptions o;
  o.weak_slip_walls = weak;
  return FluidModel(test_support::case_mesh("unit_cube.geo"), o,
                    {{"boundary", BoundaryKind::slip_wall, {}, std::move(wall_velocity)}});
}

Primitive random_state(const Vec3& x) {
  return {1.0 + 0.1 * x.x(), Vec3(0.3 + x.y(), -0.2 + x.z(), 0.5 - x.x()), 2.0 + x.z()};
}

}  // namespace

TEST(BoundaryConditions, SlipWallRemovesOneTwoOrThreeComponentsAtFacesEdgesAndCorners) {
  auto model = wall_cube();
  model.set_state(random_state);
  for (Index a = 0; a < model.mesh().num_nodes(); ++a) {
    const Vec3& x = model.positions()[std::size_t(a)];
    const int on = count_on_boundary(x);
    EXPECT_EQ(int(model.boundaries().wall_constraints(a).size()), on) << "node " << a;
    const Primitive s = model.primitive(a);
    const Primitive given = random_state(x);
    for (int j = 0; j < 3; ++j) {
      const bool constrained = x[j] < 1e-9 || x[j] > 1 - 1e-9;
      EXPECT_NEAR(s.velocity[j], constrained ? 0.0 : given.velocity[j], 1e-12);
    }
    EXPECT_NEAR(s.pressure, given.pressure, 1e-12);  // the wall keeps the pressure
    EXPECT_DOUBLE_EQ(s.rho, given.rho);
  }
}

TEST(BoundaryConditions, MovingSlipWallImposesOnlyTheNormalWallVelocity) {
  const Vec3 v_wall(0.3, -0.1, 0.2);
  auto model = wall_cube([&](Index, const Vec3&, double) { return v_wall; });
  model.set_state(random_state);
  for (Index a = 0; a < model.mesh().num_nodes(); ++a) {
    const Vec3& x = model.positions()[std::size_t(a)];
    const Primitive s = model.primitive(a);
    const Primitive given = random_state(x);
    for (int j = 0; j < 3; ++j) {
      const bool constrained = x[j] < 1e-9 || x[j] > 1 - 1e-9;
      EXPECT_NEAR(s.velocity[j], constrained ? v_wall[j] : given.velocity[j], 1e-12);
    }
  }
}

TEST(BoundaryConditions, WeakSlipWallsLeaveTheNodesFreeAndTakeTheWallsFlux) {
  // Weak walls project nothing at the nodes; their flux correction is the integral of
  // N_a (F(U) - F(U*)) . n over the wall faces. For a uniform state U with velocity u on the
  // cube (wall velocity v_w): U* has the normal velocity v_w . n, so the corrections of the
  // mass row sum to dt rho (u - v_w) . n A over each face of the cube, the energy row to
  // dt (rho E + p) u.n - (rho E* + p) v_w.n summed likewise: every face of the cube alike, the
  // sum over the six faces is zero for the mass and the energy, and the momentum rows sum to
  // dt rho sum_faces A [u (u.n) - u* (v_w.n)].
  const Vec3 v_wall(0.3, -0.1, 0.2), u(0.5, 0.2, -0.4);
  auto model = wall_cube([&](Index, const Vec3&, double) { return v_wall; }, true);
  const Primitive given{1.2, u, 2.0};
  model.set_state([&](const Vec3&) { return given; });
  for (Index a = 0; a < model.mesh().num_nodes(); ++a) EXPECT_EQ(model.primitive(a).velocity, u) << "node " << a;
  FluidState r;
  r.resize(model.mesh().num_nodes());
  r.fill_zero();
  const double dt = 0.01;
  const IdealGas gas;
  model.boundaries().add_weak_wall_flux(gas, 0.0, dt, model.positions(), model.state(), r);
  Conservative sum{0.0, Vec3::Zero(), 0.0};
  for (Index a = 0; a < r.size(); ++a) {
    const Conservative q = r.get(a);
    sum.rho += q.rho;
    sum.momentum += q.momentum;
    sum.energy += q.energy;
  }
  Vec3 momentum = Vec3::Zero();
  for (int j = 0; j < 3; ++j)
    for (const double side : {-1.0, 1.0}) {
      const Vec3 n = side * Vec3::Unit(j);
      const Vec3 u_star = u + (v_wall - u).dot(n) * n;
      momentum += dt * given.rho * (u * u.dot(n) - u_star * v_wall.dot(n));
    }
  EXPECT_NEAR(sum.rho, 0.0, 1e-15);
  EXPECT_NEAR(sum.energy, 0.0, 1e-14);
  EXPECT_LT((sum.momentum - momentum).norm(), 1e-14) << sum.momentum.transpose() << " vs " << momentum.transpose();
  // A node inside the face x = 1 (uniform G = F(U).n - F(U*).n there): every row is its
  // share of the face times G, the share read off the mass row; the shares add up to less than
  // the face's area (the rim nodes hold the rest).
  const Vec3 n = Vec3::UnitX();
  const Vec3 u_star = u + (v_wall - u).dot(n) * n;
  const double e = given.pressure / (gas.gamma - 1.0) + 0.5 * given.rho * u.squaredNorm();
  const double e_star = given.pressure / (gas.gamma - 1.0) + 0.5 * given.rho * u_star.squaredNorm();
  const double g_mass = given.rho * (u - v_wall).dot(n);
  const Vec3 g_momentum = given.rho * (u * u.dot(n) - u_star * v_wall.dot(n));
  const double g_energy = (e + given.pressure) * u.dot(n) - (e_star + given.pressure) * v_wall.dot(n);
  double shares = 0.0;
  int inside = 0;
  for (Index a = 0; a < r.size(); ++a) {
    const Vec3& x = model.positions()[std::size_t(a)];
    if (!(x.x() > 1 - 1e-9 && count_on_boundary(x) == 1)) continue;
    const Conservative q = r.get(a);
    const double share = q.rho / (dt * g_mass);
    EXPECT_GT(share, 0.0);
    EXPECT_LT((q.momentum - dt * share * g_momentum).norm(), 1e-14) << "node " << a;
    EXPECT_NEAR(q.energy, dt * share * g_energy, 1e-14) << "node " << a;
    shares += share;
    ++inside;
  }
  EXPECT_GT(inside, 0);
  EXPECT_GT(shares, 0.5);
  EXPECT_LT(shares, 1.0);
}

TEST(BoundaryConditions, ConsistentMassSweepsKeepTheWallConstraints) {
  // Strong walls inside the consistent-mass sweeps: after impose_wall_increments the new
  // state meets (u - v_w) . n = 0 at every wall node, with its pressure kept; other nodes keep
  // their increments.
  const Vec3 v_wall(0.3, -0.1, 0.2);
  auto model = wall_cube([&](Index, const Vec3&, double) { return v_wall; });
  model.set_state(random_state);
  const FluidState& old = model.state();
  FluidState d;
  d.resize(old.size());
  for (Index a = 0; a < d.size(); ++a) d.set(a, {0.01 * (a % 5), Vec3(0.3, -0.2, 0.1), 0.05});
  const IdealGas gas;
  model.boundaries().impose_wall_increments(gas, 0.0, model.positions(), old, d);
  for (Index a = 0; a < d.size(); ++a) {
    const Vec3& x = model.positions()[std::size_t(a)];
    const Conservative q = old.get(a), dq = d.get(a);
    const Conservative next{q.rho + dq.rho, q.momentum + dq.momentum, q.energy + dq.energy};
    EXPECT_DOUBLE_EQ(dq.rho, 0.01 * (a % 5));
    if (count_on_boundary(x) == 0) {
      EXPECT_EQ(dq.momentum, Vec3(0.3, -0.2, 0.1));
      EXPECT_EQ(dq.energy, 0.05);
      continue;
    }
    const Vec3 velocity = next.momentum / next.rho;
    for (int j = 0; j < 3; ++j)
      if (x[j] < 1e-9 || x[j] > 1 - 1e-9) {
        EXPECT_NEAR(velocity[j], v_wall[j], 1e-12) << "node " << a;
      }
    const Conservative unconstrained{q.rho + dq.rho, q.momentum + Vec3(0.3, -0.2, 0.1), q.energy + 0.05};
    EXPECT_NEAR(to_primitive(gas, next).pressure, to_primitive(gas, unconstrained).pressure, 1e-12);
  }
}

TEST(BoundaryConditions, BadConditionsStopWithAMessageNamingTheGroup) {
  const auto mesh = test_support::case_mesh("tube_nx100.geo");
  FluidOptions o;
  auto message = [&](std::vector<BoundaryCondition> bcs) {
    try {
      FluidModel model(mesh, o, std::move(bcs));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const BoundaryCondition left{"left", BoundaryKind::slip_wall, {}, {}};
  const BoundaryCondition right{"right", BoundaryKind::slip_wall, {}, {}};
  const BoundaryCondition sides{"sides", BoundaryKind::symmetry, {}, {}};
  EXPECT_NE(message({left, right}).find("'sides'"), std::string::npos);
  EXPECT_NE(message({left, right, sides, {"nowhere", BoundaryKind::symmetry, {}, {}}}).find("nowhere"),
            std::string::npos);
  const BoundaryCondition subsonic{"left", BoundaryKind::supersonic_inflow, {1.0, Vec3(0.5, 0, 0), 1.0 / 1.4}, {}};
  const auto m = message({subsonic, right, sides});
  EXPECT_NE(m.find("Mach 0.5"), std::string::npos) << m;
  EXPECT_NE(message({left, left, right, sides}).find("two conditions"), std::string::npos);
}

TEST(BoundaryConditions, NegativePressureStopsWithNodeTimeAndStateAndKeepsTheLastState) {
  FluidOptions o;
  FluidModel model(test_support::case_mesh("tube_nx100.geo"), o,
                   {{"left", BoundaryKind::slip_wall, {}, {}},
                    {"right", BoundaryKind::slip_wall, {}, {}},
                    {"sides", BoundaryKind::symmetry, {}, {}}});
  model.set_state([](const Vec3& x) {
    return x.x() < 0.5 ? Primitive{1.0, Vec3::Zero(), 1.0} : Primitive{1.0, Vec3::Zero(), 1e-4};
  });
  const double dt = 8.0 * model.stable_dt(1.0);  // far above the stable limit
  std::string error;
  FluidState last;
  double t_last = 0;
  for (int i = 0; i < 50 && error.empty(); ++i) {
    last = model.state();
    t_last = model.time();
    try {
      model.step(dt);
    } catch (const SolverError& e) {
      error = e.what();
    }
  }
  ASSERT_FALSE(error.empty());
  EXPECT_NE(error.find("node"), std::string::npos) << error;
  EXPECT_NE(error.find("t = "), std::string::npos) << error;
  EXPECT_NE(error.find("p = "), std::string::npos) << error;
  EXPECT_EQ(model.time(), t_last);
  EXPECT_EQ(model.state().var[4], last.var[4]);
}

TEST(BoundaryConditions, InvertingMeshUpdateStopsAndKeepsTheLastState) {
  FluidOptions o;
  FluidModel model(test_support::case_mesh("tube_nx100.geo"), o,
                   {{"left", BoundaryKind::slip_wall, {}, {}},
                    {"right", BoundaryKind::slip_wall, {}, {}},
                    {"sides", BoundaryKind::symmetry, {}, {}}});
  model.set_state([](const Vec3&) { return Primitive{1.0, Vec3::Zero(), 1.0}; });
  std::vector<Vec3> x(model.positions().begin(), model.positions().end());
  const std::vector<Vec3> x0 = x;
  for (auto& p : x)
    if (std::abs(p.x() - 0.5) < 1e-9) p.x() += 0.02;  // beyond its neighbour at 0.51
  try {
    model.step(1e-4, x);
    FAIL() << "no error";
  } catch (const SolverError& e) {
    EXPECT_NE(std::string(e.what()).find("inverted"), std::string::npos) << e.what();
  }
  EXPECT_EQ(model.time(), 0.0);
  EXPECT_EQ(model.positions()[0], x0[0]);
  for (std::size_t a = 0; a < x0.size(); ++a) ASSERT_EQ(model.positions()[a], x0[a]);
}

TEST(WallForce, UniformPressureOnAClosedSurfaceGivesNoNetForceAndPushesAWallOutward) {
  FluidOptions o;
  FluidModel model(test_support::case_mesh("tube_nx100.geo"), o,
                   {{"left", BoundaryKind::slip_wall, {}, {}},
                    {"right", BoundaryKind::slip_wall, {}, {}},
                    {"sides", BoundaryKind::symmetry, {}, {}}});
  model.set_state([](const Vec3&) { return Primitive{1.0, Vec3::Zero(), 2.5}; });
  const Vec3 total = model.pressure_force("left") + model.pressure_force("right") + model.pressure_force("sides");
  EXPECT_LT(total.norm(), 1e-14);
  // The gas pushes the wall at x = 0 towards -x with p times its area.
  const Vec3 left = model.pressure_force("left");
  EXPECT_NEAR(left.x(), -2.5 * 0.02 * 0.02, 1e-15);
  EXPECT_NEAR(left.y(), 0.0, 1e-15);
}

TEST(BoundaryConditions, CflAboveTheStableLimitIsRejected) {
  FluidOptions o;
  FluidModel model(test_support::case_mesh("tube_nx100.geo"), o,
                   {{"left", BoundaryKind::slip_wall, {}, {}},
                    {"right", BoundaryKind::slip_wall, {}, {}},
                    {"sides", BoundaryKind::symmetry, {}, {}}});
  model.set_state([](const Vec3&) { return Primitive{1.0, Vec3::Zero(), 1.0}; });
  EXPECT_GT(model.stable_dt(0.5), 0.0);
  try {
    model.stable_dt(1.5);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("CFL number 1.5"), std::string::npos) << e.what();
  }
  EXPECT_THROW(model.step_local(-0.1), InputError);
}

TEST(BoundaryConditions, NoSlipWallImposesTheWallVelocityAndTemperatureAndOutranksSymmetry) {
  FluidOptions o;
  Viscosity v;
  v.law = ViscosityLaw::constant;
  v.mu_ref = 1e-3;
  o.gas = IdealGas(1.4, 287.05, v);
  const Vec3 v_wall(0.05, 0.3, -0.2);  // also normal to the symmetry planes: no-slip wins
  const double t_wall = 0.004;
  FluidModel model(test_support::case_mesh("tube_nx100.geo"), o,
                   {BoundaryCondition::no_slip("left", [&](Index, const Vec3&, double) { return v_wall; }),
                    BoundaryCondition::no_slip("right", {}, t_wall),
                    {"sides", BoundaryKind::symmetry, {}, {}}});
  EXPECT_EQ(model.boundaries().adiabatic_wall_faces().size(), std::size_t(model.mesh().group("left").elements.size()));
  const auto given = [](const Vec3& x) {
    return Primitive{1.0 + 0.1 * x.x(), Vec3(0.3 + x.x(), 0.2, -0.1), 2.0 + x.x()};
  };
  model.set_state(given);
  int left = 0, right = 0;
  for (Index a = 0; a < model.mesh().num_nodes(); ++a) {
    const Vec3& x = model.positions()[std::size_t(a)];
    const Primitive s = model.primitive(a);
    const Primitive g = given(x);
    EXPECT_DOUBLE_EQ(s.rho, g.rho);
    if (x.x() < 1e-9) {  // adiabatic: velocity of the wall, the given pressure kept
      ++left;
      EXPECT_LT((s.velocity - v_wall).norm(), 1e-14);
      EXPECT_NEAR(s.pressure, g.pressure, 1e-12);
    } else if (x.x() > 1 - 1e-9) {  // isothermal fixed wall
      ++right;
      EXPECT_LT(s.velocity.norm(), 1e-14);
      EXPECT_NEAR(o.gas.temperature(s.rho, s.pressure), t_wall, 1e-15);
    } else {  // symmetry planes y = 0, 0.02 and z = 0, 0.02: the normal components removed
      EXPECT_NEAR(s.velocity.x(), g.velocity.x(), 1e-14);
      EXPECT_NEAR(s.velocity.y(), 0.0, 1e-14);
      EXPECT_NEAR(s.velocity.z(), 0.0, 1e-14);
    }
  }
  EXPECT_EQ(left, 4);
  EXPECT_EQ(right, 4);
  EXPECT_THROW(FluidModel(test_support::case_mesh("tube_nx100.geo"), FluidOptions{},
                          {BoundaryCondition::no_slip("left"),
                           BoundaryCondition::no_slip("right"),
                           {"sides", BoundaryKind::symmetry, {}, {}}}),
               InputError);  // inviscid gas
}

TEST(WallForce, EulerTractionIsPressureTimesTheNormalAndTheForceIsThePressureForce) {
  FluidOptions o;
  FluidModel model(test_support::case_mesh("tube_nx100.geo"), o,
                   {{"left", BoundaryKind::slip_wall, {}, {}},
                    {"right", BoundaryKind::slip_wall, {}, {}},
                    {"sides", BoundaryKind::symmetry, {}, {}}});
  model.set_state([](const Vec3& x) { return Primitive{1.0, Vec3::Zero(), 2.0 + x.x()}; });
  const WallTraction w = model.wall_traction("right");
  ASSERT_EQ(w.nodes.size(), 4u);
  for (std::size_t s = 0; s < w.nodes.size(); ++s) {
    EXPECT_LT((w.normal[s] - Vec3::UnitX()).norm(), 1e-14);
    EXPECT_LT((w.traction[s] - 3.0 * Vec3::UnitX()).norm(), 1e-13);  // pushed out of the gas
    EXPECT_EQ(w.shear[s], Vec3::Zero());
  }
  for (const char* g : {"left", "right", "sides"})
    EXPECT_LT((model.viscous_force(g) - model.pressure_force(g)).norm(), 1e-16) << g;
}

TEST(BoundaryConditions, ConsistentMassSweepsKeepTheNoSlipIncrements) {
  // The Jacobi sweeps of the consistent mass re-impose the Dirichlet increments: at no-slip
  // nodes the new momentum is (rho + d rho) u_wall, and the energy follows T_wall when
  // isothermal; the density increment and adiabatic energy stay free.
  FluidOptions o;
  Viscosity v;
  v.law = ViscosityLaw::constant;
  v.mu_ref = 1e-3;
  o.gas = IdealGas(1.4, 287.05, v);
  const Vec3 v_wall(0.0, 0.4, 0.1);
  const double t_wall = 0.003;
  FluidModel model(test_support::case_mesh("tube_nx100.geo"), o,
                   {BoundaryCondition::no_slip("left", [&](Index, const Vec3&, double) { return v_wall; }),
                    BoundaryCondition::no_slip("right", {}, t_wall),
                    {"sides", BoundaryKind::symmetry, {}, {}}});
  model.set_state([](const Vec3& x) { return Primitive{1.0 + x.x(), Vec3(0.2, 0.1, 0.0), 1.0}; });
  const FluidState& old = model.state();
  FluidState d;
  d.resize(old.size());
  for (Index a = 0; a < d.size(); ++a) d.set(a, {0.01 * (a % 5), Vec3(0.3, -0.2, 0.1), 0.05});
  model.boundaries().impose_dirichlet_increments(o.gas, 0.0, model.positions(), old, d);
  for (Index a = 0; a < d.size(); ++a) {
    const double x = model.positions()[std::size_t(a)].x();
    const Conservative q = old.get(a), dq = d.get(a);
    const Conservative next{q.rho + dq.rho, q.momentum + dq.momentum, q.energy + dq.energy};
    EXPECT_DOUBLE_EQ(dq.rho, 0.01 * (a % 5));
    if (x < 1e-9) {
      EXPECT_LT((next.momentum / next.rho - v_wall).norm(), 1e-14);
      EXPECT_DOUBLE_EQ(dq.energy, 0.05);
    } else if (x > 1 - 1e-9) {
      EXPECT_LT(next.momentum.norm(), 1e-14);
      const Primitive p = to_primitive(o.gas, next);
      EXPECT_NEAR(o.gas.temperature(p.rho, p.pressure), t_wall, 1e-15);
    } else {
      EXPECT_EQ(dq.momentum, Vec3(0.3, -0.2, 0.1));
    }
  }
}

TEST(BoundaryNormals, AreRecomputedWhereTheirFacetsLeaveThePlaneAndRestoredWhenTheyComeBack) {
  const mesh::Mesh cube = test_support::case_mesh("unit_cube.geo");
  const IdealGas gas;
  const std::vector<BoundaryCondition> slip = {{"boundary", BoundaryKind::slip_wall, {}, {}}};
  const auto constraints = [&](const BoundarySet& b) {
    std::vector<std::vector<Vec3>> c(cube.nodes.size());
    for (Index a = 0; a < cube.num_nodes(); ++a) {
      const auto n = b.wall_constraints(a);
      c[std::size_t(a)].assign(n.begin(), n.end());
    }
    return c;
  };
  BoundarySet b(cube, cube.cells.connectivity, gas, slip);
  b.update_normals(cube.nodes);
  EXPECT_EQ(b.normals_updated(), Index(std::count_if(cube.nodes.begin(), cube.nodes.end(),
                                                     [](const Vec3& x) { return count_on_boundary(x) > 0; })));
  const auto reference = constraints(b);
  // The top z = 1 bulges out; the nodes of x = 0 slide within their plane.
  std::vector<Vec3> x = cube.nodes;
  for (Vec3& p : x) {
    if (p.z() > 1 - 1e-9) p.z() += 0.1 * std::sin(3.14159 * p.x()) * std::sin(3.14159 * p.y());
    if (p.x() < 1e-9) p.y() += 0.02 * std::sin(3.14159 * p.y()) * p.z();
  }
  b.update_normals(x);
  Index top = 0;
  for (const Vec3& p : cube.nodes) top += p.z() > 1 - 1e-9;
  EXPECT_GE(b.normals_updated(), top);  // the top face and its edges
  EXPECT_LT(b.normals_updated(), 2 * top);
  // What a boundary set built on the moved mesh computes at every node.
  mesh::Mesh moved = cube;
  moved.nodes = x;
  BoundarySet fresh(moved, moved.cells.connectivity, gas, slip);
  fresh.update_normals(x);
  const auto expected = constraints(fresh), got = constraints(b);
  for (std::size_t a = 0; a < x.size(); ++a) {
    ASSERT_EQ(got[a].size(), expected[a].size()) << "node " << a;
    for (std::size_t k = 0; k < got[a].size(); ++k)
      EXPECT_LT((got[a][k] - expected[a][k]).norm(), 1e-14) << "node " << a;
  }
  // Back at the reference: the reference normals, bit for bit.
  b.update_normals(cube.nodes);
  EXPECT_EQ(constraints(b), reference);
}
