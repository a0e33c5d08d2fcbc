// The Taylor–Galerkin element kernel: flux Jacobian products, exact free-stream residual.
#include <gtest/gtest.h>

#include <random>

#include "fluid_test_util.h"
#include "shellflow/fluid/element_kernel.h"
#include "shellflow/fluid/mass.h"
#include "shellflow/fluid/ordering.h"
#include "shellflow/fluid/residual.h"

using namespace shellflow;
using namespace shellflow::fluid;

namespace {

std::array<double, 5> flux(double gamma, const std::array<double, 5>& u, int dir) {
  const double rho = u[0];
  const Vec3 vel(u[1] / rho, u[2] / rho, u[3] / rho);
  const double p = (gamma - 1) * (u[4] - 0.5 * rho * vel.squaredNorm());
  std::array<double, 5> f{};
  f[0] = u[1 + dir];
  for (int i = 0; i < 3; ++i) f[std::size_t(1 + i)] = u[std::size_t(1 + i)] * vel[dir];
  f[std::size_t(1 + dir)] += p;
  f[4] = (u[4] + p) * vel[dir];
  return f;
}

}  // namespace

TEST(ElementKernel, JacobianProductMatchesFiniteDifferenceOfTheFlux) {
  const double gamma = 1.4;
  const std::array<double, 5> u = {1.3, 0.4, -0.7, 0.2, 3.1};
  const double d[5] = {0.3, -0.2, 0.5, 0.1, -0.4};
  detail::MeanState s{};
  s.rho = u[0];
  double mu = 0;
  for (int j = 0; j < 3; ++j) {
    s.m[j] = u[std::size_t(1 + j)];
    s.vel[j] = s.m[j] / s.rho;
    s.w[j] = 0.1 * (j + 1);
    mu += s.m[j] * s.vel[j];
  }
  s.enthalpy = u[4] + (gamma - 1) * (u[4] - 0.5 * mu);
  for (const bool relative : {false, true}) {
    const detail::KernelConstants k{gamma - 1, 0.0, relative, true, true};
    for (int dir = 0; dir < 3; ++dir) {
      double out[5];
      detail::apply_jacobian(k, s, dir, d, out);
      const double eps = 1e-6;
      std::array<double, 5> up = u, um = u;
      for (int v = 0; v < 5; ++v) {
        up[std::size_t(v)] += eps * d[v];
        um[std::size_t(v)] -= eps * d[v];
      }
      const auto fp = flux(gamma, up, dir), fm = flux(gamma, um, dir);
      for (int v = 0; v < 5; ++v) {
        const double expected =
            (fp[std::size_t(v)] - fm[std::size_t(v)]) / (2 * eps) - (relative ? s.w[dir] * d[v] : 0.0);
        EXPECT_NEAR(out[v], expected, 1e-8) << "dir " << dir << " row " << v;
      }
    }
  }
}

TEST(ElementKernel, UniformStateGivesExactlyZeroResidualForAnyMeshVelocity) {
  auto m = test_support::case_mesh("unit_cube.geo");
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-0.02, 0.02), speed(-2.0, 2.0), nu(0.0, 0.1);
  for (auto& x : m.nodes)
    if (x.minCoeff() > 1e-9 && x.maxCoeff() < 1 - 1e-9) x += Vec3(jitter(rng), jitter(rng), jitter(rng));
  const auto colours = colour_cells(m.cells.connectivity, 4, m.num_nodes(), 97);
  std::vector<Index> tets;
  for (const Index c : colours.order) {
    const auto cell = m.cells.element(c);
    tets.insert(tets.end(), cell.begin(), cell.end());
  }
  TetGeometry g;
  compute_geometry(m.nodes, tets, g);
  IdealGas gas;
  FluidState u;
  u.resize(m.num_nodes());
  const Conservative q = to_conservative(gas, {1.2, Vec3(2.1, 0.4, -0.3), 0.9});
  for (Index a = 0; a < m.num_nodes(); ++a) u.set(a, q);
  std::vector<Vec3> w(m.nodes.size());
  for (auto& v : w) v = Vec3(speed(rng), speed(rng), speed(rng));
  std::vector<double> viscosity(std::size_t(m.num_cells()));
  for (auto& v : viscosity) v = nu(rng);
  FluidState r;
  r.resize(m.num_nodes());
  ResidualParameters p;
  p.gas = gas;
  p.dt = 1e-3;
  assemble_residual(p, {tets, colours.block_offsets, colours.colour_offsets}, g, u, w, viscosity, r);
  for (int v = 0; v < num_variables; ++v)
    for (const double x : r.var[std::size_t(v)]) ASSERT_EQ(x, 0.0);
}

TEST(ElementKernel, ConvectiveResidualOfALinearMassFluxIsItsDivergence) {
  // rho u linear in x with rho = 1 ... the mass row of -D_e is -div(rho u) exactly (P1
  // interpolation of a linear flux), so with dt = 1, no TG term (dt^2 scaled down), the
  // lumped increment at an interior node equals -div(m).
  auto m = test_support::case_mesh("unit_cube.geo");
  const auto colours = colour_cells(m.cells.connectivity, 4, m.num_nodes(), 97);
  std::vector<Index> tets;
  for (const Index c : colours.order) {
    const auto cell = m.cells.element(c);
    tets.insert(tets.end(), cell.begin(), cell.end());
  }
  TetGeometry g;
  compute_geometry(m.nodes, tets, g);
  FluidState u, r;
  u.resize(m.num_nodes());
  r.resize(m.num_nodes());
  for (Index a = 0; a < m.num_nodes(); ++a) {
    const Vec3& x = m.nodes[std::size_t(a)];
    u.set(a, {1.0, Vec3(0.5 * x.x(), -0.25 * x.y(), 0.125 * x.z()), 10.0});
  }
  std::vector<Vec3> w(m.nodes.size(), Vec3::Zero());
  const double dt = 1e-8;
  ResidualParameters p;
  p.dt = dt;
  p.mesh_moves = false;
  assemble_residual(p, {tets, colours.block_offsets, colours.colour_offsets}, g, u, w, {}, r);
  for (Index a = 0; a < m.num_nodes(); ++a) {
    const Vec3& x = m.nodes[std::size_t(a)];
    if (x.minCoeff() < 1e-9 || x.maxCoeff() > 1 - 1e-9) continue;
    const double rate = r.var[0][std::size_t(a)] / g.lumped_mass[std::size_t(a)] / dt;
    ASSERT_NEAR(rate, -(0.5 - 0.25 + 0.125), 1e-6) << "node " << a;
  }
}

TEST(MassMatrix, ConsistentMassRowSumsAreTheLumpedMassAndJacobiConverges) {
  auto m = test_support::case_mesh("unit_cube.geo");
  const auto colours = colour_cells(m.cells.connectivity, 4, m.num_nodes(), 97);
  std::vector<Index> tets;
  for (const Index c : colours.order) {
    const auto cell = m.cells.element(c);
    tets.insert(tets.end(), cell.begin(), cell.end());
  }
  const ElementLoop loop{tets, colours.block_offsets, colours.colour_offsets};
  TetGeometry g;
  compute_geometry(m.nodes, tets, g);
  FluidState ones, out, r, dx, work;
  for (auto* s : {&ones, &out, &r, &dx, &work}) s->resize(m.num_nodes());
  for (auto& v : ones.var) std::fill(v.begin(), v.end(), 1.0);
  apply_consistent_mass(loop, g, ones, out);
  for (Index a = 0; a < m.num_nodes(); ++a)
    ASSERT_NEAR(out.var[2][std::size_t(a)], g.lumped_mass[std::size_t(a)], 1e-15);
  // r = M_C x for a smooth x; more Jacobi sweeps approach x.
  FluidState x = ones;
  for (Index a = 0; a < m.num_nodes(); ++a)
    x.var[0][std::size_t(a)] = std::sin(3 * m.nodes[std::size_t(a)].x()) + m.nodes[std::size_t(a)].y();
  apply_consistent_mass(loop, g, x, r);
  // The lumped-preconditioned Jacobi iteration contracts oscillatory modes by 0.8 per
  // sweep (element eigenvalues of M_L^-1 M_C: 1/5 and 1), smooth ones much faster.
  double previous = 1e300, first = 0.0;
  for (const int iterations : {0, 1, 3, 10}) {
    solve_consistent_mass(loop, g, r, iterations, dx, work);
    double err = 0;
    for (Index a = 0; a < m.num_nodes(); ++a)
      err = std::max(err, std::abs(dx.var[0][std::size_t(a)] - x.var[0][std::size_t(a)]));
    EXPECT_LT(err, previous) << iterations << " iterations";
    if (iterations == 0) first = err;
    previous = err;
  }
  EXPECT_LT(previous, 0.2 * first);
}
