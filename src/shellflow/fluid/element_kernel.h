#pragma once
// Internal: the per-tetrahedron computation of the Taylor–Galerkin residual (fluid.md §4.2),
// shared by the element pass and the natural-boundary term. Gradients, divergences and the
// flux difference are formed from differences to node 0 (fluid.md §11), so a uniform state
// gives exactly zero whatever the geometry and mesh velocity.
//
// The kernel is written once for a number type `Real`: `double` for one element, or a
// short vector of doubles (SIMD pack, one element per lane) for the element pass, which
// runs several elements through the same arithmetic at once. Every lane performs exactly
// the operations of the scalar version.
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

/// Mean state of the element, for the flux Jacobian.
template <class Real>
struct MeanStateOf {
  Real rho, m[3], vel[3], enthalpy, w[3];
};
using MeanState = MeanStateOf<double>;

/// The direction-independent part of A_k d: velocity and pressure perturbations.
template <class Real>
struct JacobianCommon {
  Real du[3];
  Real dp;
};

template <class Real>
inline JacobianCommon<Real> jacobian_common(const KernelConstants& k, const MeanStateOf<Real>& s,
                                            const Real d[num_variables]) {
  const Real inv_rho = 1.0 / s.rho;
  JacobianCommon<Real> c;
  for (int j = 0; j < 3; ++j) c.du[j] = (d[1 + j] - s.vel[j] * d[0]) * inv_rho;
  const Real u_dm = s.vel[0] * d[1] + s.vel[1] * d[2] + s.vel[2] * d[3];
  const Real u2 = s.vel[0] * s.vel[0] + s.vel[1] * s.vel[1] + s.vel[2] * s.vel[2];
  c.dp = k.gamma_minus_1 * (d[4] - u_dm + 0.5 * u2 * d[0]);
  return c;
}

/// out = (A_dir - [relative] w̄_dir I) d from the common part c of d.
template <class Real>
inline void jacobian_direction(const KernelConstants& k, const MeanStateOf<Real>& s, const JacobianCommon<Real>& c,
                               int dir, const Real d[num_variables], Real out[num_variables]) {
  const Real uk = s.vel[dir];
  out[0] = d[1 + dir];
  for (int i = 0; i < 3; ++i) out[1 + i] = uk * d[1 + i] + s.m[i] * c.du[dir];
  out[1 + dir] += c.dp;
  out[4] = uk * d[4] + s.enthalpy * c.du[dir] + uk * c.dp;
  if (k.relative_velocity)
    for (int v = 0; v < num_variables; ++v) out[v] -= s.w[dir] * d[v];
}

/// out = (A_k - [relative] w̄_k I) d, A_k the Euler flux Jacobian at the mean state.
template <class Real>
inline void apply_jacobian(const KernelConstants& k, const MeanStateOf<Real>& s, int dir, const Real d[num_variables],
                           Real out[num_variables]) {
  jacobian_direction(k, s, jacobian_common(k, s, d), dir, d, out);
}

/// One element (Real = double) or one element per lane (Real = SIMD pack).
template <class Real>
struct ElementData {
  Real volume;
  Real grad[4][3];  // B_a,j
  Real u[4][num_variables];
  Real w[4][3];  // set only when the mesh moves
  // derived
  Real grad_u[num_variables][3];  // (dU_r / dx_j)_e
  Real flux_div[num_variables];   // D_e
  Real mesh_term[num_variables];  // (w̄ . grad) U
  Real w_mean[3];
  Real tg_flux[3][num_variables];  // Ã_k R̂_e
  Real tg_mesh[num_variables];     // C2 bracket
};

using ElementState = ElementData<double>;

inline void load_element(std::span<const Index> tets, Index e, const TetGeometry& g, const FluidState& u,
                         std::span<const Vec3> w, bool mesh_moves, ElementState& s) {
  const auto ue = std::size_t(e);
  s.volume = g.volume[ue];
  for (int a = 0; a < 4; ++a) {
    const Index n = tets[4 * ue + std::size_t(a)];
    for (int j = 0; j < 3; ++j) s.grad[a][j] = g.grad[ue][std::size_t(3 * a + j)];
    for (int v = 0; v < num_variables; ++v) s.u[a][v] = u.var[std::size_t(v)][std::size_t(n)];
    if (mesh_moves) {
      const Vec3& wn = w[std::size_t(n)];
      for (int j = 0; j < 3; ++j) s.w[a][j] = wn[j];
    }
  }
}

/// Makes `v` a rounded value: the compiler may not fuse the product that produced it into a
/// later add (fused multiply-add). Equal nodal values then give differences of exactly zero,
/// as without contraction: fma(a, b, -round(a b)) is the rounding error, not 0.
template <class Real>
inline void rounded(Real& v) {
  asm("" : "+x"(v));
}

template <class Real>
inline void compute_element(const KernelConstants& k, ElementData<Real>& s) {
  const auto& B = s.grad;
  // Nodal velocity and pressure, rounded before their differences are formed.
  Real vel[4][3], p[4];
  for (int a = 0; a < 4; ++a) {
    const Real inv_rho = 1.0 / s.u[a][0];
    for (int j = 0; j < 3; ++j) {
      vel[a][j] = s.u[a][1 + j] * inv_rho;
      rounded(vel[a][j]);
    }
    p[a] =
        k.gamma_minus_1 * (s.u[a][4] - 0.5 * (s.u[a][1] * vel[a][0] + s.u[a][2] * vel[a][1] + s.u[a][3] * vel[a][2]));
    rounded(p[a]);
  }
  // Differences to node 0: gradients of U, velocity and p.
  Real du[4][num_variables], dvel[4][3], dp[4];
  for (int a = 1; a < 4; ++a) {
    for (int v = 0; v < num_variables; ++v) du[a][v] = s.u[a][v] - s.u[0][v];
    for (int j = 0; j < 3; ++j) dvel[a][j] = vel[a][j] - vel[0][j];
    dp[a] = p[a] - p[0];
  }
  for (int v = 0; v < num_variables; ++v)
    for (int j = 0; j < 3; ++j) s.grad_u[v][j] = du[1][v] * B[1][j] + du[2][v] * B[2][j] + du[3][v] * B[3][j];
  // Group divergence D = sum_a B_a,j F_j(U_a) in difference form: with the product rule
  // F(U_a) - F(U_0) = dU_a vel_a + U_0 dvel_a (+ dp_a for momentum), so
  //   D_i = sum_a dU_a,i (B_a . vel_a) + U_0,i div(vel) [+ (grad p)_i].
  Real b_vel[4];
  for (int a = 1; a < 4; ++a) b_vel[a] = B[a][0] * vel[a][0] + B[a][1] * vel[a][1] + B[a][2] * vel[a][2];
  Real div_vel = B[1][0] * dvel[1][0] + B[2][0] * dvel[2][0] + B[3][0] * dvel[3][0];
  Real grad_p[3];
  for (int j = 0; j < 3; ++j) {
    if (j > 0) div_vel += B[1][j] * dvel[1][j] + B[2][j] * dvel[2][j] + B[3][j] * dvel[3][j];
    grad_p[j] = dp[1] * B[1][j] + dp[2] * B[2][j] + dp[3] * B[3][j];
  }
  s.flux_div[0] = s.grad_u[1][0] + s.grad_u[2][1] + s.grad_u[3][2];  // div(rho u)
  for (int i = 0; i < 3; ++i)
    s.flux_div[1 + i] = du[1][1 + i] * b_vel[1] + du[2][1 + i] * b_vel[2] + du[3][1 + i] * b_vel[3] +
                        s.u[0][1 + i] * div_vel + grad_p[i];
  s.flux_div[4] = (du[1][4] + dp[1]) * b_vel[1] + (du[2][4] + dp[2]) * b_vel[2] + (du[3][4] + dp[3]) * b_vel[3] +
                  (s.u[0][4] + p[0]) * div_vel;

  MeanStateOf<Real> m;
  Real mean[num_variables];
  for (int v = 0; v < num_variables; ++v) mean[v] = 0.25 * (s.u[0][v] + s.u[1][v] + s.u[2][v] + s.u[3][v]);
  m.rho = mean[0];
  const Real inv_rho = 1.0 / mean[0];
  for (int j = 0; j < 3; ++j) {
    m.m[j] = mean[1 + j];
    m.vel[j] = mean[1 + j] * inv_rho;
  }
  const Real m_u = m.m[0] * m.vel[0] + m.m[1] * m.vel[1] + m.m[2] * m.vel[2];
  m.enthalpy = mean[4] + k.gamma_minus_1 * (mean[4] - 0.5 * m_u);
  // Element residual R̂ = -D + (w̄ . grad) U.
  Real rhat[num_variables];
  if (k.mesh_moves) {
    for (int j = 0; j < 3; ++j) {
      s.w_mean[j] = 0.25 * (s.w[0][j] + s.w[1][j] + s.w[2][j] + s.w[3][j]);
      m.w[j] = s.w_mean[j];
    }
    for (int v = 0; v < num_variables; ++v) {
      s.mesh_term[v] = s.w_mean[0] * s.grad_u[v][0] + s.w_mean[1] * s.grad_u[v][1] + s.w_mean[2] * s.grad_u[v][2];
      rhat[v] = s.mesh_term[v] - s.flux_div[v];
    }
  } else {
    for (int j = 0; j < 3; ++j) m.w[j] = s.w_mean[j] = Real{};
    for (int v = 0; v < num_variables; ++v) {
      s.mesh_term[v] = Real{};
      rhat[v] = -s.flux_div[v];
    }
  }
  const KernelConstants k_fixed{k.gamma_minus_1, k.dt, false, false, false};  // w̄ = 0
  const KernelConstants& kj = k.mesh_moves ? k : k_fixed;
  const JacobianCommon<Real> c = jacobian_common(kj, m, rhat);
  for (int dir = 0; dir < 3; ++dir) jacobian_direction(kj, m, c, dir, rhat, s.tg_flux[dir]);
  for (int v = 0; v < num_variables; ++v) s.tg_mesh[v] = Real{};
  if (k.moving_mesh_correction && k.mesh_moves) {
    // C2: Ã_k [ (div w) dU/dx_k + (dw_j/dx_k) dU/dx_j ], w linear in the element.
    Real gw[3][3];  // gw[k][j] = d w_j / d x_k
    for (int kk = 0; kk < 3; ++kk)
      for (int j = 0; j < 3; ++j)
        gw[kk][j] = (s.w[1][j] - s.w[0][j]) * B[1][kk] + (s.w[2][j] - s.w[0][j]) * B[2][kk] +
                    (s.w[3][j] - s.w[0][j]) * B[3][kk];
    const Real div_w = gw[0][0] + gw[1][1] + gw[2][2];
    for (int dir = 0; dir < 3; ++dir) {
      Real z[num_variables];
      for (int v = 0; v < num_variables; ++v)
        z[v] = div_w * s.grad_u[v][dir] + gw[dir][0] * s.grad_u[v][0] + gw[dir][1] * s.grad_u[v][1] +
               gw[dir][2] * s.grad_u[v][2];
      Real az[num_variables];
      apply_jacobian(k, m, dir, z, az);
      for (int v = 0; v < num_variables; ++v) s.tg_mesh[v] += az[v];
    }
  }
}

/// The element's contributions value[a][v] to the nodal residuals (fluid.md §4.2 table).
/// `dt` is the step of the first-order rows (1 with local stepping: the nodal dt_a is
/// applied when scattering), `dt_element` the second factor of the Taylor–Galerkin rows
/// (fluid.md §4.3).
template <class Real>
inline void element_contributions(const KernelConstants& k, const ElementData<Real>& s, const Real& viscosity,
                                  const Real& dt, const Real& dt_element, Real value[4][num_variables]) {
  const auto& B = s.grad;
  const Real V = s.volume;
  const Real c_flux = -0.25 * dt * V;
  const Real c_tg = 0.5 * dt * dt_element * V;
  const Real c_visc = -dt * V * viscosity;
  for (int v = 0; v < num_variables; ++v) {
    // Node-independent part, and the vector that B_a multiplies (TG term + diffusion).
    const Real common = c_flux * s.flux_div[v];
    Real g[3];
    for (int j = 0; j < 3; ++j) g[j] = c_tg * s.tg_flux[j][v] + c_visc * s.grad_u[v][j];
    for (int a = 0; a < 4; ++a) value[a][v] = common + B[a][0] * g[0] + B[a][1] * g[1] + B[a][2] * g[2];
  }
  if (!k.mesh_moves) return;
  const Real c_mesh = dt * V / 20.0;
  const Real c_tg_mesh = 0.125 * dt * dt_element * V;
  for (int v = 0; v < num_variables; ++v) {
    const Real common = 4.0 * c_mesh * s.mesh_term[v] + c_tg_mesh * s.tg_mesh[v];
    for (int a = 0; a < 4; ++a)
      value[a][v] +=
          common + c_mesh * (s.w[a][0] * s.grad_u[v][0] + s.w[a][1] * s.grad_u[v][1] + s.w[a][2] * s.grad_u[v][2]);
  }
}

}  // namespace shellflow::fluid::detail
