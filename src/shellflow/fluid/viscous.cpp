#include "shellflow/fluid/viscous.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "shellflow/core/error.h"

namespace shellflow::fluid {

const char* to_string(ViscosityLaw law) {
  switch (law) {
    case ViscosityLaw::none:
      return "none";
    case ViscosityLaw::constant:
      return "constant";
    case ViscosityLaw::sutherland:
      return "sutherland";
    case ViscosityLaw::power:
      return "power";
  }
  return "?";
}

void check_viscosity(const IdealGas& gas) {
  const Viscosity& v = gas.viscosity;
  if (!v.viscous()) return;
  auto fail = [&](const char* name, double value, const char* need) {
    throw InputError(
        fmt::format("fluid viscosity ({} law): {} = {} must be {}; air has "
                    "mu_ref = 1.716e-5 Pa s, t_ref = 273.15 K, sutherland = "
                    "110.4 K, prandtl = 0.72",
                    to_string(v.law), name, value, need));
  };
  if (!(v.mu_ref > 0.0) || !std::isfinite(v.mu_ref)) fail("mu_ref", v.mu_ref, "positive");
  if (!(v.prandtl > 0.0) || !std::isfinite(v.prandtl)) fail("prandtl", v.prandtl, "positive");
  if (v.law == ViscosityLaw::sutherland || v.law == ViscosityLaw::power)
    if (!(v.t_ref > 0.0) || !std::isfinite(v.t_ref)) fail("t_ref", v.t_ref, "positive");
  if (v.law == ViscosityLaw::power && !(v.exponent >= 0.0 && v.exponent <= 2.0))
    fail("exponent", v.exponent, "in [0, 2]");
  if (v.law == ViscosityLaw::sutherland) {
    if (!(v.sutherland >= 0.0) || !std::isfinite(v.sutherland)) fail("sutherland", v.sutherland, "non-negative");
  }
}

namespace {

inline std::array<double, 4> velocity_temperature(double gm1, double inv_r, const FluidState& u, std::size_t n) {
  const double inv_rho = 1.0 / u.var[0][n];
  const double vx = u.var[1][n] * inv_rho, vy = u.var[2][n] * inv_rho, vz = u.var[3][n] * inv_rho;
  const double p = gm1 * (u.var[4][n] - 0.5 * (u.var[1][n] * vx + u.var[2][n] * vy + u.var[3][n] * vz));
  return {vx, vy, vz, p * inv_rho * inv_r};
}

/// Fluxes from the nodal velocity/temperature q[a] of the element's nodes. Gradients from
/// differences to node 0: exactly zero for a uniform state.
struct Fluxes {
  double tau[3][3];  // symmetric
  double energy[3];  // tau_ij ū_i + k dT/dx_j
  double conduction[3];
  double mean_velocity[3];
  double mu;
};

inline void compute_fluxes(const IdealGas& gas, const std::array<double, 4>* const q[4], const double* B, Fluxes& f) {
  double g[4][3] = {};  // g[c][j] = d q_c / d x_j
  for (int a = 1; a < 4; ++a)
    for (int c = 0; c < 4; ++c) {
      const double d = (*q[a])[std::size_t(c)] - (*q[0])[std::size_t(c)];
      for (int j = 0; j < 3; ++j) g[c][j] += d * B[3 * a + j];
    }
  double mean[4];
  for (int c = 0; c < 4; ++c)
    mean[c] =
        0.25 * ((*q[0])[std::size_t(c)] + (*q[1])[std::size_t(c)] + (*q[2])[std::size_t(c)] + (*q[3])[std::size_t(c)]);
  f.mu = gas.viscosity.dynamic(mean[3]);
  const double k = gas.conductivity(f.mu);
  const double div_part = (2.0 / 3.0) * f.mu * (g[0][0] + g[1][1] + g[2][2]);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) f.tau[i][j] = f.mu * (g[i][j] + g[j][i]);
    f.tau[i][i] -= div_part;
    f.mean_velocity[i] = mean[i];
  }
  for (int j = 0; j < 3; ++j) {
    f.conduction[j] = k * g[3][j];
    f.energy[j] = f.tau[0][j] * mean[0] + f.tau[1][j] * mean[1] + f.tau[2][j] * mean[2] + f.conduction[j];
  }
}

}  // namespace

ElementViscousFlux element_viscous_flux(const IdealGas& gas, const Index* nodes, const double* B, const FluidState& u) {
  const double gm1 = gas.gamma - 1.0, inv_r = 1.0 / gas.gas_constant;
  std::array<double, 4> q[4];
  const std::array<double, 4>* qp[4];
  for (int a = 0; a < 4; ++a) {
    q[a] = velocity_temperature(gm1, inv_r, u, std::size_t(nodes[a]));
    qp[a] = &q[a];
  }
  Fluxes f;
  compute_fluxes(gas, qp, B, f);
  ElementViscousFlux out;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) out.stress(i, j) = f.tau[i][j];
    out.conduction[i] = f.conduction[i];
    out.mean_velocity[i] = f.mean_velocity[i];
  }
  out.viscosity = f.mu;
  return out;
}

void add_viscous_residual(const IdealGas& gas, double dt, std::span<const double> nodal_dt, const ElementLoop& loop,
                          const TetGeometry& g, const FluidState& u, FluidState& r, NodalVelocityTemperature& q) {
  const Index nn = u.size();
  q.resize(std::size_t(nn));
  const double gm1 = gas.gamma - 1.0, inv_r = 1.0 / gas.gas_constant;
  for_each_node(nn, [&](Index a) { q[std::size_t(a)] = velocity_temperature(gm1, inv_r, u, std::size_t(a)); });
  const bool local = !nodal_dt.empty();
  std::array<double*, num_variables> out{};
  for (int v = 0; v < num_variables; ++v) out[std::size_t(v)] = r.var[std::size_t(v)].data();
  for_each_element(loop, [&](Index e) {
    const auto ue = std::size_t(e);
    const Index* nodes = loop.tets.data() + 4 * ue;
    const double* B = g.grad[ue].data();
    const std::array<double, 4>* qe[4] = {&q[std::size_t(nodes[0])], &q[std::size_t(nodes[1])],
                                          &q[std::size_t(nodes[2])], &q[std::size_t(nodes[3])]};
    Fluxes f;
    compute_fluxes(gas, qe, B, f);
    const double c = -g.volume[ue] * (local ? 1.0 : dt);
    for (int a = 0; a < 4; ++a) {
      const double* b = B + 3 * a;
      const auto node = std::size_t(nodes[a]);
      const double scale = local ? c * nodal_dt[node] : c;
      for (int i = 0; i < 3; ++i)
        out[std::size_t(1 + i)][node] += scale * (f.tau[i][0] * b[0] + f.tau[i][1] * b[1] + f.tau[i][2] * b[2]);
      out[4][node] += scale * (f.energy[0] * b[0] + f.energy[1] * b[1] + f.energy[2] * b[2]);
    }
  });
}

void add_wall_work(const IdealGas& gas, double dt, std::span<const double> nodal_dt, std::span<const Index> tets,
                   std::span<const Vec3> x, const TetGeometry& g, const FluidState& u,
                   std::span<const BoundaryFace> faces, FluidState& r) {
  // Serial: wall faces are few, and neighbouring faces share nodes.
  for (const auto& face : faces) {
    const auto ue = std::size_t(face.element);
    const ElementViscousFlux f = element_viscous_flux(gas, tets.data() + 4 * ue, g.grad[ue].data(), u);
    const Vec3 area = face_area_vector(x, face);  // outward, |area| = A_f
    const Vec3 traction = f.stress * area;        // tau_ij n_j A_f
    std::array<double, 3> work{};                 // tau_ij u_i n_j A_f at the face nodes
    double sum = 0.0;
    for (int k = 0; k < 3; ++k) {
      const auto n = std::size_t(face.nodes[std::size_t(k)]);
      const double inv_rho = 1.0 / u.var[0][n];
      work[std::size_t(k)] =
          (traction[0] * u.var[1][n] + traction[1] * u.var[2][n] + traction[2] * u.var[3][n]) * inv_rho;
      sum += work[std::size_t(k)];
    }
    // ∫_f N_a N_b dA = A_f (1 + delta_ab) / 12.
    for (int k = 0; k < 3; ++k) {
      const auto n = std::size_t(face.nodes[std::size_t(k)]);
      const double dt_a = nodal_dt.empty() ? dt : nodal_dt[n];
      r.var[4][n] += dt_a * (sum + work[std::size_t(k)]) / 12.0;
    }
  }
}

void element_diffusivity(const IdealGas& gas, std::span<const Index> tets, const FluidState& u,
                         std::span<const double> artificial, std::vector<double>& out) {
  const auto ne = static_cast<Index>(tets.size() / 4);
  out.resize(std::size_t(ne));
  const double factor = std::max(1.0, gas.gamma / gas.viscosity.prandtl);
  const double inv_r = 1.0 / gas.gas_constant;
  for_each_element_index(ne, [&](Index e) {
    const auto ue = std::size_t(e);
    double rho = 0.0, temperature = 0.0;
    for (int a = 0; a < 4; ++a) {
      const auto n = std::size_t(tets[4 * ue + std::size_t(a)]);
      const double rho_a = u.var[0][n];
      const double p = gas.pressure(rho_a, u.var[1][n], u.var[2][n], u.var[3][n], u.var[4][n]);
      rho += 0.25 * rho_a;
      temperature += 0.25 * p / rho_a * inv_r;
    }
    const double nu = factor * gas.viscosity.dynamic(temperature) / rho;
    out[ue] = (artificial.empty() ? 0.0 : artificial[ue]) + nu;
  });
}

}  // namespace shellflow::fluid
