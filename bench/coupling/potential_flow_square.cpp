// The clamped square of cases/panel_3d/clamped_square.yaml (0.5 m, 1.35 mm aluminium, air rho 0.339 kg/m^3,
// p 28 kPa) under 3-D linearised supersonic potential flow (tests/coupling/potential_flow_reference.h) against
// first-order piston theory, both on the Ritz plate of tests/coupling/plate_flutter_reference.h with the modes
// symmetric about mid-span (the half model's). Prints the mode convergence at Mach 3.5, a Mach sweep and the onset
// Mach of each (docs/coupling.md, "3-D panels"). Not a Google Benchmark: one run prints the table.
//   bench_potential_flow_square [--quick]
#include <chrono>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <vector>

#include "coupling/potential_flow_reference.h"

namespace {

using namespace shellflow::testing;
using potential_reference::cplx;

struct Model {
  plate_reference::Plate plate;
  std::vector<int> modes;
  Eigen::MatrixXd M, K, A0, A1;
};

Model model(int modes_x, int modes_y) {
  Model m;
  m.plate.x_edges = m.plate.y_edges = plate_reference::Edge::clamped;
  m.plate.modes_x = modes_x;
  m.plate.modes_y = modes_y;
  for (int i = 0; i < modes_x; ++i)
    for (int j = 0; j < modes_y; j += 2) m.modes.push_back(i * modes_y + j);
  const plate_reference::Matrices r = plate_reference::assemble(m.plate);
  m.M = r.M(m.modes, m.modes);
  m.K = r.K(m.modes, m.modes);
  m.A0 = r.A0(m.modes, m.modes);
  m.A1 = r.A1(m.modes, m.modes);
  return m;
}

potential_reference::Flow air(double mach) { return potential_reference::flow_from(0.339, 28000.0, 1.4, mach); }

/// The least stable root of piston theory (f = -qA (w_x + g_D w_t)).
cplx piston_root(const Model& m, double mach) {
  const auto f = air(mach);
  const auto pt = plate_reference::piston_theory(f.rho, f.U(), mach);
  const Eigen::VectorXcd r = potential_reference::quadratic_roots(m.M, (pt.qA * pt.g_D * m.A0).cast<cplx>(),
                                                                  (m.K + pt.qA * m.A1).cast<cplx>());
  Eigen::Index k = 0;
  r.real().maxCoeff(&k);
  return {r(k).real(), std::abs(r(k).imag())};
}

cplx potential_root(const Model& m, double mach, cplx start) {
  const potential_reference::Aerodynamics aero(m.plate, m.modes, air(mach));
  return potential_reference::flutter_root(
             m.M, m.K, [&](cplx s) { return aero.matrix(s); }, start)
      .s;
}

double hz(cplx s) { return std::abs(s.imag()) / (2.0 * std::numbers::pi); }

/// Mach number where Re s of piston theory crosses zero (bisection on [lo, hi]).
double piston_onset(const Model& m, double lo, double hi) {
  while (hi - lo > 1e-7) {
    const double mid = 0.5 * (lo + hi);
    (piston_root(m, mid).real() > 0.0 ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

/// The zero of the parabola through (x_k, y_k), k = 0..2, nearest x_2 (Newton from the chord's zero).
double parabola_zero(const std::vector<double>& x, const std::vector<double>& y) {
  Eigen::Matrix3d V;
  Eigen::Vector3d b;
  for (int k = 0; k < 3; ++k) {
    const double d = x[k] - x[2];
    V.row(k) << 1.0, d, d * d;
    b(k) = y[k];
  }
  const Eigen::Vector3d c = V.partialPivLu().solve(b);  // y = c0 + c1 d + c2 d^2, d = x - x_2
  double d = -c(0) / c(1);
  for (int it = 0; it < 50; ++it) d -= (c(0) + c(1) * d + c(2) * d * d) / (c(1) + 2.0 * c(2) * d);
  return x[2] + d;
}

struct Onset {
  double mach, hz;
  double machs[3], sigma[3];
};

/// Steps of 0.005 in Mach down from `from` while the root (followed from `start`) has sigma > 4 1/s; the onset is the
/// zero of the parabola through the last three (Mach, sigma).
template <class RootAt>
Onset onset_by_extrapolation(const RootAt& root_at, double from, cplx start) {
  std::vector<double> machs = {from}, sigma;
  cplx s = root_at(from, {std::max(start.real(), 5.0), start.imag()});
  sigma.push_back(s.real());
  while (sigma.back() > 4.0 || sigma.size() < 3) {
    machs.push_back(machs.back() - 0.005);
    s = root_at(machs.back(), s);
    sigma.push_back(s.real());
  }
  const std::vector<double> x(machs.end() - 3, machs.end()), y(sigma.end() - 3, sigma.end());
  return {parabola_zero(x, y), hz(s), {x[0], x[1], x[2]}, {y[0], y[1], y[2]}};
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  std::printf("Mode convergence at Mach 3.5 (modes x by y, the spanwise-symmetric ones kept)\n");
  std::printf(
      "| modes | kept | piston sigma [1/s] | f [Hz] | potential sigma [1/s] | f [Hz] | difference | time [s] |\n");
  std::printf("|---|---|---|---|---|---|---|---|\n");
  std::vector<std::pair<int, int>> counts = {{4, 3}, {6, 5}, {8, 5}, {10, 7}};
  if (quick) counts.resize(2);
  for (const auto& [mx, my] : counts) {
    const Model m = model(mx, my);
    const auto t0 = std::chrono::steady_clock::now();
    const cplx p = piston_root(m, 3.5), s = potential_root(m, 3.5, p);
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("| %d x %d | %zu | %.3f | %.3f | %.3f | %.3f | %+.3f (%+.2f %%) | %.1f |\n", mx, my, m.modes.size(),
                p.real(), hz(p), s.real(), hz(s), s.real() - p.real(), 100.0 * (s.real() / p.real() - 1.0), t);
  }

  const Model m = model(quick ? 6 : 8, 5);
  std::printf("\nMach sweep (%d x 5 modes)\n| Mach | piston sigma | f | potential sigma | f |\n|---|---|---|---|---|\n",
              m.plate.modes_x);
  std::vector<double> machs = {4.0, 3.5, 3.25, 3.1, 3.0, 2.97};
  std::vector<double> sig;
  for (const double mach : machs) {
    const cplx p = piston_root(m, mach), s = potential_root(m, mach, {std::max(p.real(), 5.0), p.imag()});
    sig.push_back(s.real());
    std::printf("| %.2f | %.3f | %.3f | %.3f | %.3f |\n", mach, p.real(), hz(p), s.real(), hz(s));
  }
  // The potential-flow matrix is an integral where Re s > 0: step down in Mach while sigma > 4 1/s, then the parabola
  // through the last three points to sigma = 0. Piston theory by the same steps checks the extrapolation against
  // its bisection.
  const auto potential = [&](double mach, cplx start) { return potential_root(m, mach, start); };
  const auto piston = [&](double mach, cplx) { return piston_root(m, mach); };
  std::printf("\nonset Mach (steps of 0.005 in Mach while sigma > 4 1/s, the parabola through the last three):\n");
  const Onset op = onset_by_extrapolation(potential, 2.97, piston_root(m, 2.97));
  std::printf("  potential flow %.4f (sigma %.2f, %.2f, %.2f 1/s at Mach %.3f, %.3f, %.3f; %.3f Hz)\n", op.mach,
              op.sigma[0], op.sigma[1], op.sigma[2], op.machs[0], op.machs[1], op.machs[2], op.hz);
  const Onset pp = onset_by_extrapolation(piston, 2.97, {});
  std::printf("  piston theory %.4f (sigma %.2f, %.2f, %.2f 1/s at Mach %.3f, %.3f, %.3f); by bisection %.4f\n",
              pp.mach, pp.sigma[0], pp.sigma[1], pp.sigma[2], pp.machs[0], pp.machs[1], pp.machs[2],
              piston_onset(m, 2.5, 3.5));
  return 0;
}
