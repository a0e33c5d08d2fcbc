#pragma once
// Internal: the per-tetrahedron computation of the Taylor–Galerkin residual (fluid.md §4.2),
// shared by the element pass and the natural-boundary term. Gradients, divergences and the
// flux difference are formed from differences to node 0 (fluid.md §11), so a uniform state
// gives exactly zero whatever the geometry and mesh velocity.
#include <array>
#include <span>

#include "shellflow/fluid/geometry.h"
#include "shellflow/fluid/state.h"

namespace shellflow::fluid::detail {

struct KernelConstants {
  double gamma_minus_1;
  double dt;
  bool relative_velocity;
  bool moving_mesh_correction;
  bool mesh_moves;  ///< false: w = 0 everywhere, the ALE and C2 terms vanish and are skipped
};

struct ElementState {
  std::array<Index, 4> nodes;
  double volume;
  const double* grad;  // B_a,j at [3 a + j]
  double u[4][num_variables];
  double w[4][3];
  // derived
  double grad_u[num_variables][3];  // (dU_r / dx_j)_e
  double flux_div[num_variables];   // D_e
  double mesh_term[num_variables];  // (w̄ . grad) U
  double w_mean[3];
  double tg_flux[3][num_variables];  // Ã_k R̂_e
  double tg_mesh[num_variables];     // C2 bracket
};

inline void load_element(std::span<const Index> tets, Index e, const TetGeometry& g,
                         const FluidState& u, std::span<const Vec3> w, bool mesh_moves,
                         ElementState& s) {
  const auto ue = std::size_t(e);
  s.volume = g.volume[ue];
  s.grad = g.grad[ue].data();
  for (int a = 0; a < 4; ++a) {
    const Index n = tets[4 * ue + std::size_t(a)];
    s.nodes[std::size_t(a)] = n;
    for (int v = 0; v < num_variables; ++v) s.u[a][v] = u.var[std::size_t(v)][std::size_t(n)];
    if (mesh_moves) {
      const Vec3& wn = w[std::size_t(n)];
      for (int j = 0; j < 3; ++j) s.w[a][j] = wn[j];
    } else {
      for (int j = 0; j < 3; ++j) s.w[a][j] = 0.0;
    }
  }
}

/// Mean state of the element, for the flux Jacobian.
struct MeanState {
  double rho, m[3], vel[3], enthalpy, w[3];
};

/// out = (A_k - [relative] w̄_k I) d, A_k the Euler flux Jacobian at the mean state.
inline void apply_jacobian(const KernelConstants& k, const MeanState& s, int dir,
                           const double d[num_variables], double out[num_variables]) {
  const double inv_rho = 1.0 / s.rho;
  double du[3];
  double u_dm = 0.0;
  double u2 = 0.0;
  for (int j = 0; j < 3; ++j) {
    du[j] = (d[1 + j] - s.vel[j] * d[0]) * inv_rho;
    u_dm += s.vel[j] * d[1 + j];
    u2 += s.vel[j] * s.vel[j];
  }
  const double dp = k.gamma_minus_1 * (d[4] - u_dm + 0.5 * u2 * d[0]);
  const double uk = s.vel[dir];
  out[0] = d[1 + dir];
  for (int i = 0; i < 3; ++i) out[1 + i] = uk * d[1 + i] + s.m[i] * du[dir];
  out[1 + dir] += dp;
  out[4] = uk * d[4] + s.enthalpy * du[dir] + uk * dp;
  if (k.relative_velocity)
    for (int v = 0; v < num_variables; ++v) out[v] -= s.w[dir] * d[v];
}

inline void compute_element(const KernelConstants& k, ElementState& s) {
  const double* B = s.grad;
  // Nodal inviscid fluxes F_j(U_a).
  double flux[4][num_variables][3];
  for (int a = 0; a < 4; ++a) {
    const double inv_rho = 1.0 / s.u[a][0];
    const double vel[3] = {s.u[a][1] * inv_rho, s.u[a][2] * inv_rho, s.u[a][3] * inv_rho};
    const double p = k.gamma_minus_1 *
                     (s.u[a][4] - 0.5 * (s.u[a][1] * vel[0] + s.u[a][2] * vel[1] +
                                         s.u[a][3] * vel[2]));
    for (int j = 0; j < 3; ++j) {
      flux[a][0][j] = s.u[a][1 + j];
      for (int i = 0; i < 3; ++i) flux[a][1 + i][j] = s.u[a][1 + i] * vel[j];
      flux[a][1 + j][j] += p;
      flux[a][4][j] = (s.u[a][4] + p) * vel[j];
    }
  }
  for (int v = 0; v < num_variables; ++v) {
    double div = 0.0;
    double gr[3] = {0.0, 0.0, 0.0};
    for (int a = 1; a < 4; ++a) {
      const double du = s.u[a][v] - s.u[0][v];
      for (int j = 0; j < 3; ++j) {
        div += B[3 * a + j] * (flux[a][v][j] - flux[0][v][j]);
        gr[j] += du * B[3 * a + j];
      }
    }
    s.flux_div[v] = div;
    for (int j = 0; j < 3; ++j) s.grad_u[v][j] = gr[j];
  }
  MeanState m{};
  double mean[num_variables];
  for (int v = 0; v < num_variables; ++v)
    mean[v] = 0.25 * (s.u[0][v] + s.u[1][v] + s.u[2][v] + s.u[3][v]);
  for (int j = 0; j < 3; ++j) {
    s.w_mean[j] = 0.25 * (s.w[0][j] + s.w[1][j] + s.w[2][j] + s.w[3][j]);
    m.w[j] = s.w_mean[j];
  }
  m.rho = mean[0];
  double m_u = 0.0;
  for (int j = 0; j < 3; ++j) {
    m.m[j] = mean[1 + j];
    m.vel[j] = mean[1 + j] / mean[0];
    m_u += m.m[j] * m.vel[j];
  }
  m.enthalpy = mean[4] + k.gamma_minus_1 * (mean[4] - 0.5 * m_u);
  // Element residual R̂ = -D + (w̄ . grad) U.
  double rhat[num_variables];
  for (int v = 0; v < num_variables; ++v) {
    s.mesh_term[v] = s.w_mean[0] * s.grad_u[v][0] + s.w_mean[1] * s.grad_u[v][1] +
                     s.w_mean[2] * s.grad_u[v][2];
    rhat[v] = -s.flux_div[v] + s.mesh_term[v];
  }
  for (int dir = 0; dir < 3; ++dir) apply_jacobian(k, m, dir, rhat, s.tg_flux[dir]);
  for (int v = 0; v < num_variables; ++v) s.tg_mesh[v] = 0.0;
  if (k.moving_mesh_correction && k.mesh_moves) {
    // C2: Ã_k [ (div w) dU/dx_k + (dw_j/dx_k) dU/dx_j ], w linear in the element.
    double gw[3][3] = {};  // gw[k][j] = d w_j / d x_k
    for (int a = 1; a < 4; ++a)
      for (int kk = 0; kk < 3; ++kk)
        for (int j = 0; j < 3; ++j) gw[kk][j] += (s.w[a][j] - s.w[0][j]) * B[3 * a + kk];
    const double div_w = gw[0][0] + gw[1][1] + gw[2][2];
    for (int dir = 0; dir < 3; ++dir) {
      double z[num_variables];
      for (int v = 0; v < num_variables; ++v)
        z[v] = div_w * s.grad_u[v][dir] + gw[dir][0] * s.grad_u[v][0] +
               gw[dir][1] * s.grad_u[v][1] + gw[dir][2] * s.grad_u[v][2];
      double az[num_variables];
      apply_jacobian(k, m, dir, z, az);
      for (int v = 0; v < num_variables; ++v) s.tg_mesh[v] += az[v];
    }
  }
}

/// Adds the element's contribution to the nodal residuals (fluid.md §4.2 table).
/// Global stepping: dt_element = k.dt and nodal_dt = nullptr. Local stepping (steady runs,
/// fluid.md §4.3): first-order rows scale with the nodal dt_a, the Taylor–Galerkin rows with
/// dt_a dt_element.
inline void scatter_element(const KernelConstants& k, const ElementState& s, double viscosity,
                            double dt_element, const double* nodal_dt,
                            const std::array<double*, num_variables>& out) {
  const double* B = s.grad;
  const double V = s.volume;
  const double dt = nodal_dt ? 1.0 : k.dt;  // nodal factor applied at the end when local
  const double c_flux = -dt * V / 4.0;
  const double c_mesh = dt * V / 20.0;
  const double c_tg = 0.5 * dt * dt_element * V;
  const double c_tg_mesh = 0.5 * dt * dt_element * V / 4.0;
  const double c_visc = -dt * V * viscosity;
  for (int v = 0; v < num_variables; ++v) {
    // Node-independent part, and the vector that B_a multiplies (TG term + diffusion).
    double common = c_flux * s.flux_div[v];
    if (k.mesh_moves) common += 4.0 * c_mesh * s.mesh_term[v] + c_tg_mesh * s.tg_mesh[v];
    double g[3];
    for (int j = 0; j < 3; ++j) g[j] = c_tg * s.tg_flux[j][v] + c_visc * s.grad_u[v][j];
    for (int a = 0; a < 4; ++a) {
      const double* b = B + 3 * a;
      double value = common + b[0] * g[0] + b[1] * g[1] + b[2] * g[2];
      if (k.mesh_moves)
        value += c_mesh * (s.w[a][0] * s.grad_u[v][0] + s.w[a][1] * s.grad_u[v][1] +
                           s.w[a][2] * s.grad_u[v][2]);
      const auto node = std::size_t(s.nodes[std::size_t(a)]);
      out[std::size_t(v)][node] += nodal_dt ? nodal_dt[node] * value : value;
    }
  }
}

}  // namespace shellflow::fluid::detail
