#pragma once
// Element kernel of the 7-parameter positional shell (shell.md §1–§6): strain energy,
// internal force, consistent tangent and constant mass of one curved triangle. It knows
// nothing of assembly, supports or time stepping.
//
// Unknowns of one element, node-major, 7 per node (shell.md §2.5, increment form):
//   u_e = [dx_0 (3), dG_0 (3), a_0 | dx_1 ... ],  dx = x - X, dG = G - V, a.
// `Tri` is fem::Tri3, fem::Tri6 or fem::Tri10 (Gmsh node order).
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "shellflow/core/types.h"
#include "shellflow/fem/quadrature.h"
#include "shellflow/fem/shape_functions.h"
#include "shellflow/shell/material.h"

namespace shellflow::shell {

inline constexpr int dofs_per_node = 7;

/// Quadrature of the shell volume: an in-plane triangle rule times Gauss–Legendre through
/// the thickness, with the shape functions tabulated at the in-plane points.
template <class Tri>
struct ShellQuadrature {
  static constexpr int num_nodes = Tri::num_nodes;
  using Values = Eigen::Matrix<double, num_nodes, 1>;
  using Gradients = Eigen::Matrix<double, num_nodes, 2>;

  std::vector<double> plane_weights;      ///< sum to 1/2 (reference triangle area)
  std::vector<Values> phi;                ///< phi[q](j)
  std::vector<Gradients> dphi;            ///< dphi[q](j, alpha) = dphi_j / dxi_alpha
  std::vector<double> thickness_points;   ///< xi3 in [-1, 1]
  std::vector<double> thickness_weights;  ///< sum to 2

  /// Defaults (shell.md §5): degree 6 in the plane (12 points), 3 Gauss points through the
  /// thickness (the spec's [decision]; the papers' point counts are unverified). A higher
  /// degree / 5 points serve as a convergence check.
  explicit ShellQuadrature(int plane_degree = 6, int thickness_count = 3) {
    const fem::QuadratureRule& plane = fem::triangle_rule(plane_degree);
    const fem::QuadratureRule& line = fem::line_rule(thickness_count);
    for (int q = 0; q < plane.size(); ++q) {
      plane_weights.push_back(plane.weights[static_cast<std::size_t>(q)]);
      Values N;
      Eigen::Matrix<double, num_nodes, 2, Eigen::RowMajor> dN;
      Tri::eval(plane.point(q).data(), N.data());
      Tri::eval_gradients(plane.point(q).data(), dN.data());
      phi.push_back(N);
      dphi.push_back(dN);
    }
    thickness_points = line.points;
    thickness_weights = line.weights;
  }
  int plane_size() const { return static_cast<int>(plane_weights.size()); }
  int thickness_size() const { return static_cast<int>(thickness_weights.size()); }
  int size() const { return plane_size() * thickness_size(); }
};

/// Initial geometry of one element and what never changes: nodal mid-surface points X,
/// unit directors V and thicknesses h, and A0^-1 and dV = w J0 at every volume point.
template <class Tri>
struct ShellElementGeometry {
  static constexpr int num_nodes = Tri::num_nodes;
  static constexpr int num_dofs = dofs_per_node * num_nodes;
  using NodeVectors = Eigen::Matrix<double, 3, num_nodes>;
  using NodeScalars = Eigen::Matrix<double, num_nodes, 1>;

  NodeVectors X;
  NodeVectors V;
  NodeScalars h;
  std::vector<Mat3> A0_inverse;  ///< index q * thickness_size + k
  std::vector<double> dV;        ///< w J0 (reference volume of the point)
  double min_J0 = 0.0;           ///< smallest J0 (must be > 0)

  ShellElementGeometry() = default;
  ShellElementGeometry(const NodeVectors& X_, const NodeVectors& V_, const NodeScalars& h_,
                       const ShellQuadrature<Tri>& rule)
      : X(X_), V(V_), h(h_) {
    min_J0 = std::numeric_limits<double>::infinity();
    for (int q = 0; q < rule.plane_size(); ++q) {
      const auto& N = rule.phi[static_cast<std::size_t>(q)];
      const auto& dN = rule.dphi[static_cast<std::size_t>(q)];
      const Vec3 V_hat = V * N;
      const double h_hat = h.dot(N);
      for (int k = 0; k < rule.thickness_size(); ++k) {
        const double xi3 = rule.thickness_points[static_cast<std::size_t>(k)];
        Mat3 A0;
        for (int al = 0; al < 2; ++al) {
          const double h_al = h.dot(dN.col(al));
          A0.col(al) = X * dN.col(al) + 0.5 * xi3 * (h_al * V_hat + h_hat * (V * dN.col(al)));
        }
        A0.col(2) = 0.5 * h_hat * V_hat;
        const double J0 = A0.determinant();
        min_J0 = std::min(min_J0, J0);
        A0_inverse.push_back(A0.inverse());
        dV.push_back(rule.plane_weights[static_cast<std::size_t>(q)] *
                     rule.thickness_weights[static_cast<std::size_t>(k)] * J0);
      }
    }
  }
};

namespace detail {

/// Fields interpolated at one in-plane point from the element increments.
template <int N>
struct PlanePoint {
  Vec3 dx_d[2];  ///< d(dx)/dxi_alpha
  Vec3 dg;       ///< interpolated dG
  Vec3 dg_d[2];
  Vec3 g;  ///< current interpolated director V_hat + dg
  Vec3 g_d[2];
  double a = 0.0;
  double a_d[2] = {0.0, 0.0};
  double h = 0.0;
  double h_d[2] = {0.0, 0.0};

  template <class Tri, class Vector>
  void interpolate(const ShellElementGeometry<Tri>& geo, const Eigen::Matrix<double, N, 1>& phi,
                   const Eigen::Matrix<double, N, 2>& dphi, const Vector& u) {
    dx_d[0] = dx_d[1] = dg = dg_d[0] = dg_d[1] = Vec3::Zero();
    a = a_d[0] = a_d[1] = 0.0;
    for (int j = 0; j < N; ++j) {
      const auto dxj = u.template segment<3>(dofs_per_node * j);
      const auto dGj = u.template segment<3>(dofs_per_node * j + 3);
      const double aj = u(dofs_per_node * j + 6);
      dg += phi(j) * dGj;
      a += phi(j) * aj;
      for (int al = 0; al < 2; ++al) {
        dx_d[al] += dphi(j, al) * dxj;
        dg_d[al] += dphi(j, al) * dGj;
        a_d[al] += dphi(j, al) * aj;
      }
    }
    g = geo.V * phi + dg;
    h = geo.h.dot(phi);
    for (int al = 0; al < 2; ++al) {
      g_d[al] = geo.V * dphi.col(al) + dg_d[al];
      h_d[al] = geo.h.dot(dphi.col(al));
    }
  }

  /// Delta A = A1 - A0 at thickness coordinate xi3 (shell.md §2.5, increment form).
  Mat3 delta_A(double xi3) const {
    const double xi3_sq = xi3 * xi3;
    Mat3 dA;
    for (int al = 0; al < 2; ++al) {
      const double zeta_al = a_d[al] * xi3_sq;
      dA.col(al) = dx_d[al] + 0.5 * h_d[al] * (xi3 * dg + a * xi3_sq * g) + 0.5 * h * zeta_al * g +
                   0.5 * h * (xi3 * dg_d[al] + a * xi3_sq * g_d[al]);
    }
    dA.col(2) = 0.5 * h * (dg + 2.0 * a * xi3 * g);
    return dA;
  }
};

/// Green–Lagrange strain from H = (A1 - A0) A0^-1: E = (H + H^T + H^T H) / 2.
inline Mat3 green_lagrange(const Mat3& H) { return 0.5 * (H + H.transpose() + H.transpose() * H); }

inline Mat3 svk_stress(const Mat3& E, double lambda, double mu) {
  return lambda * E.trace() * Mat3::Identity() + 2.0 * mu * E;
}

}  // namespace detail

/// Strain energy U^e of the element at increments u (shell.md §4).
template <class Tri, class Vector>
double strain_energy(const ShellElementGeometry<Tri>& geo, const ShellQuadrature<Tri>& rule,
                     const SvkMaterial& material, const Vector& u) {
  constexpr int N = Tri::num_nodes;
  const double lambda = material.lame_lambda();
  const double mu = material.lame_mu();
  const int nt = rule.thickness_size();
  double U = 0.0;
  detail::PlanePoint<N> p;
  for (int q = 0; q < rule.plane_size(); ++q) {
    p.interpolate(geo, rule.phi[static_cast<std::size_t>(q)], rule.dphi[static_cast<std::size_t>(q)], u);
    for (int k = 0; k < nt; ++k) {
      const std::size_t ip = static_cast<std::size_t>(q * nt + k);
      const Mat3 H = p.delta_A(rule.thickness_points[static_cast<std::size_t>(k)]) * geo.A0_inverse[ip];
      const Mat3 E = detail::green_lagrange(H);
      U += 0.5 * (lambda * E.trace() * E.trace() + 2.0 * mu * E.squaredNorm()) * geo.dV[ip];
    }
  }
  return U;
}

/// Largest |E_ik| over the element's volume points (diagnostic for strain-free states).
template <class Tri, class Vector>
double max_abs_strain(const ShellElementGeometry<Tri>& geo, const ShellQuadrature<Tri>& rule, const Vector& u) {
  constexpr int N = Tri::num_nodes;
  const int nt = rule.thickness_size();
  double worst = 0.0;
  detail::PlanePoint<N> p;
  for (int q = 0; q < rule.plane_size(); ++q) {
    p.interpolate(geo, rule.phi[static_cast<std::size_t>(q)], rule.dphi[static_cast<std::size_t>(q)], u);
    for (int k = 0; k < nt; ++k) {
      const std::size_t ip = static_cast<std::size_t>(q * nt + k);
      const Mat3 H = p.delta_A(rule.thickness_points[static_cast<std::size_t>(k)]) * geo.A0_inverse[ip];
      worst = std::max(worst, detail::green_lagrange(H).cwiseAbs().maxCoeff());
    }
  }
  return worst;
}

/// Internal force f = dU/du and, when K is not null, the consistent tangent K = d2U/du2
/// including the a–G second-derivative term (shell.md §4). f and K are overwritten.
/// Returns false when det A <= 0 at some point (the state is not admissible).
///
/// Structure used for speed: at an in-plane point every first and second derivative of A1
/// with respect to a nodal parameter of node j is linear in the node's three shape values
/// Phi_j = (dphi_j/dxi1, dphi_j/dxi2, phi_j), with coefficients that do not depend on j.
/// So per volume point the whole Hessian is a 21x21 matrix Z over (parameter type t of
/// 7) x (basis m of 3), K_jk(t, s) = Phi_j^T Z(t, s) Phi_k. Z is summed over the thickness
/// points (Phi is the same for all of them) and expanded to node pairs once per in-plane
/// point, in a type-major buffer that is permuted to node-major once per element.
template <class Tri, class Vector>
bool internal_force(
    const ShellElementGeometry<Tri>& geo, const ShellQuadrature<Tri>& rule, const SvkMaterial& material,
    const Vector& u, Eigen::Matrix<double, ShellElementGeometry<Tri>::num_dofs, 1>& f,
    Eigen::Matrix<double, ShellElementGeometry<Tri>::num_dofs, ShellElementGeometry<Tri>::num_dofs>* K) {
  constexpr int N = Tri::num_nodes;
  constexpr int nd = ShellElementGeometry<Tri>::num_dofs;
  constexpr int nz = 3 * dofs_per_node;  // (type t, basis m) -> 3 t + m
  using Mat21 = Eigen::Matrix<double, nz, nz>;
  using Vec21 = Eigen::Matrix<double, nz, 1>;
  const double lambda = material.lame_lambda();
  const double mu = material.lame_mu();
  // Isotropic Voigt elasticity (engineering shear) as a sum of squares:
  // C = lambda 1 1^T (normal part) + 2 mu I_normal + mu I_shear = Lc^T Lc, Lc 7x6.
  const double s_lambda = std::sqrt(lambda), s_2mu = std::sqrt(2.0 * mu), s_mu = std::sqrt(mu);

  // Type-major tangent: Kt(t N + j, s N + k). Thread-local: 39 kB for Tri10.
  thread_local Eigen::Matrix<double, nd, nd> Kt;
  Eigen::Matrix<double, 6, nz> M;   // strain variations per (t, m), Voigt
  Eigen::Matrix<double, 7, nz> LM;  // Lc M
  Eigen::Matrix<double, 3, 6> Wb;   // A0^-T P e_m for x (m = 0..2) then G (m = 0..2)
  std::array<Mat3, 3> Da;           // dA1/da per basis m, times A0^-1
  Eigen::Matrix<double, 3, N> Phi;  // rows dphi/dxi1, dphi/dxi2, phi
  // Expansion to node pairs, batched over the in-plane points so that it is one product
  // with inner dimension 3 x (in-plane points) per type block row:
  // PhiT(j, 3 q + m) = Phi_q(m, j); Ycat(t 3nq + 3 q + m, s N + k) = (Z_q(t, s) Phi_q)(m, k).
  const int nq3 = 3 * rule.plane_size();
  thread_local Eigen::MatrixXd PhiT, Ycat;
  if (K) {
    PhiT.resize(N, nq3);
    Ycat.resize(dofs_per_node * nq3, nd);
  }
  Mat21 Z;
  Vec21 fz;

  f.setZero();
  Eigen::Matrix<double, nd, 1> ft = Eigen::Matrix<double, nd, 1>::Zero();  // type-major force
  const int nt = rule.thickness_size();
  bool admissible = true;
  detail::PlanePoint<N> p;
  for (int q = 0; q < rule.plane_size(); ++q) {
    const auto& phi = rule.phi[static_cast<std::size_t>(q)];
    const auto& dphi = rule.dphi[static_cast<std::size_t>(q)];
    p.interpolate(geo, phi, dphi, u);
    Phi.row(0) = dphi.col(0).transpose();
    Phi.row(1) = dphi.col(1).transpose();
    Phi.row(2) = phi.transpose();
    if (K) Z.setZero();
    fz.setZero();
    for (int k = 0; k < nt; ++k) {
      const std::size_t ip = static_cast<std::size_t>(q * nt + k);
      const double xi3 = rule.thickness_points[static_cast<std::size_t>(k)];
      const double xi3_sq = xi3 * xi3;
      const double dV = geo.dV[ip];
      const Mat3& A0i = geo.A0_inverse[ip];
      const Mat3 H = p.delta_A(xi3) * A0i;
      const Mat3 A = Mat3::Identity() + H;
      if (!(A.determinant() > 0.0)) admissible = false;
      const Mat3 E = detail::green_lagrange(H);
      const Mat3 S = detail::svk_stress(E, lambda, mu);
      const double zeta = xi3 + p.a * xi3_sq;
      const double zeta_d[2] = {p.a_d[0] * xi3_sq, p.a_d[1] * xi3_sq};

      // dA1/dx_{j,i} = e_i (P_x Phi_j)^T, dA1/dG_{j,i} = e_i (P_G Phi_j)^T (shell.md §4).
      const Mat3 A0it = A0i.transpose();
      Wb.col(0) = A0it.col(0);
      Wb.col(1) = A0it.col(1);
      Wb.col(2).setZero();
      Wb.col(3) = (0.5 * p.h * zeta) * A0it.col(0);
      Wb.col(4) = (0.5 * p.h * zeta) * A0it.col(1);
      {
        const Vec3 cG2(0.5 * (p.h_d[0] * zeta + p.h * zeta_d[0]), 0.5 * (p.h_d[1] * zeta + p.h * zeta_d[1]),
                       0.5 * p.h * (1.0 + 2.0 * p.a * xi3));
        Wb.col(5) = A0it * cG2;
      }
      // dA1/da_j per basis: m = 0, 1 (dphi_j/dxi_m) and m = 2 (phi_j).
      {
        Mat3 d = Mat3::Zero();
        d.col(0) = 0.5 * xi3_sq * p.h * p.g;
        Da[0] = d * A0i;
        d.col(0).setZero();
        d.col(1) = 0.5 * xi3_sq * p.h * p.g;
        Da[1] = d * A0i;
        for (int al = 0; al < 2; ++al) d.col(al) = 0.5 * xi3_sq * (p.h_d[al] * p.g + p.h * p.g_d[al]);
        d.col(2) = p.h * xi3 * p.g;
        Da[2] = d * A0i;
      }
      const auto set_strain_column = [&](int col, const Mat3& Mm) {  // Mm = A^T D
        M(0, col) = Mm(0, 0);
        M(1, col) = Mm(1, 1);
        M(2, col) = Mm(2, 2);
        M(3, col) = Mm(0, 1) + Mm(1, 0);
        M(4, col) = Mm(1, 2) + Mm(2, 1);
        M(5, col) = Mm(0, 2) + Mm(2, 0);
      };
      for (int i = 0; i < 3; ++i) {
        const Vec3 ai = A.row(i).transpose();  // A^T (e_i w^T) = a_i w^T
        for (int m = 0; m < 3; ++m) {
          set_strain_column(3 * i + m, ai * Wb.col(m).transpose());
          set_strain_column(3 * (3 + i) + m, ai * Wb.col(3 + m).transpose());
        }
      }
      for (int m = 0; m < 3; ++m) set_strain_column(18 + m, A.transpose() * Da[static_cast<std::size_t>(m)]);

      Eigen::Matrix<double, 6, 1> S_voigt;
      S_voigt << S(0, 0), S(1, 1), S(2, 2), S(0, 1), S(1, 2), S(0, 2);
      fz.noalias() += dV * (M.transpose() * S_voigt);
      if (!K) continue;

      // Material part: Z += dV M^T C M = (Lc M)^T (Lc M) dV.
      LM.row(0) = s_lambda * (M.row(0) + M.row(1) + M.row(2));
      LM.template middleRows<3>(1) = s_2mu * M.template topRows<3>();
      LM.template bottomRows<3>(3) = s_mu * M.template bottomRows<3>();
      // Only the lower block triangle (type blocks s <= t) is read below: block row t
      // needs columns 0 .. 3t+2 (43 % fewer products than the full 21x21).
      // (coefficient-based product: Eigen's blocked GEMM costs more in packing at this size)
      const Eigen::Matrix<double, 7, nz> LMw = dV * LM;
      [&]<int... T>(std::integer_sequence<int, T...>) {
        ((Z.template block<3, 3 * T + 3>(3 * T, 0).noalias() +=
          LMw.template middleCols<3>(3 * T).transpose().lazyProduct(LM.template leftCols<3 * T + 3>())),
         ...);
      }
      (std::make_integer_sequence<int, dofs_per_node>{});

      // Initial-stress part of x/G: delta_ii' w_r^T S w_s (node vectors).
      const Eigen::Matrix<double, 6, 6> P = dV * (Wb.transpose() * (S * Wb));
      for (int i = 0; i < 3; ++i) {
        Z.template block<3, 3>(3 * i, 3 * i) += P.template block<3, 3>(0, 0);
        Z.template block<3, 3>(3 * i, 3 * (3 + i)) += P.template block<3, 3>(0, 3);
        Z.template block<3, 3>(3 * (3 + i), 3 * i) += P.template block<3, 3>(3, 0);
        Z.template block<3, 3>(3 * (3 + i), 3 * (3 + i)) += P.template block<3, 3>(3, 3);
      }
      // Initial stress with `a`: (Da S) : D_s, and the a–G term B : d2A1/(da_j dG_{k,i}),
      // B = A S A0^-T; d2A1 = e_i c2^T with c2 bilinear in Phi_j, Phi_k.
      const Mat3 B = dV * (A * S * A0it);
      const Vec3 Bc22 = B * Vec3(0.5 * xi3_sq * p.h_d[0], 0.5 * xi3_sq * p.h_d[1], p.h * xi3);
      const Vec3 Bc0 = (0.5 * xi3_sq * p.h) * B.col(0);  // c2 = 0.5 xi3^2 h e_0
      const Vec3 Bc1 = (0.5 * xi3_sq * p.h) * B.col(1);
      for (int m = 0; m < 3; ++m) {
        const Mat3 DaS = dV * (Da[static_cast<std::size_t>(m)] * S);
        const Eigen::Matrix<double, 3, 6> DW = DaS * Wb;  // (Da S w)_i per (x/G, n)
        for (int i = 0; i < 3; ++i)
          for (int n = 0; n < 3; ++n) {
            const double vx = DW(i, n);
            double vG = DW(i, 3 + n);
            // c2 terms: (m = 2, n = 2), (m = al, n = 2) and (m = 2, n = al).
            if (m == 2 && n == 2) vG += Bc22(i);
            if (n == 2 && m < 2) vG += (m == 0 ? Bc0 : Bc1)(i);
            if (m == 2 && n < 2) vG += (n == 0 ? Bc0 : Bc1)(i);
            Z(18 + m, 3 * i + n) += vx;
            Z(3 * i + n, 18 + m) += vx;
            Z(18 + m, 3 * (3 + i) + n) += vG;
            Z(3 * (3 + i) + n, 18 + m) += vG;
          }
        for (int n = 0; n < 3; ++n) Z(18 + m, 18 + n) += (DaS.array() * Da[static_cast<std::size_t>(n)].array()).sum();
      }
    }
    // Expand to node pairs: f_j(t) = Phi_j^T fz(t); K_jk(t, s) = Phi_j^T Z(t, s) Phi_k.
    for (int t = 0; t < dofs_per_node; ++t)
      ft.template segment<N>(t * N).noalias() += Phi.transpose() * fz.template segment<3>(3 * t);
    if (!K) continue;
    PhiT.template middleCols<3>(3 * q) = Phi.transpose();
    // Lower block triangle only (s <= t); mirrored below.
    for (int t = 0; t < dofs_per_node; ++t)
      for (int s = 0; s <= t; ++s)
        Ycat.template block<3, N>(t * nq3 + 3 * q, s * N).noalias() = Z.template block<3, 3>(3 * t, 3 * s) * Phi;
  }
  if (K)
    for (int t = 0; t < dofs_per_node; ++t)
      Kt.block(t * N, 0, N, (t + 1) * N).noalias() = PhiT * Ycat.block(t * nq3, 0, nq3, (t + 1) * N);
  for (int j = 0; j < N; ++j)
    for (int t = 0; t < dofs_per_node; ++t) f(dofs_per_node * j + t) = ft(t * N + j);
  if (K) {
    for (int s = 0; s < dofs_per_node; ++s)
      for (int k = 0; k < N; ++k) {
        const int col = dofs_per_node * k + s;
        for (int t = 0; t < dofs_per_node; ++t)
          for (int j = 0; j < N; ++j) {
            // Kt is filled for t >= s (type blocks), i.e. the block lower triangle.
            (*K)(dofs_per_node * j + t, col) = t >= s ? Kt(t * N + j, s * N + k) : Kt(s * N + k, t * N + j);
          }
      }
  }
  return admissible;
}

/// Constant consistent mass (shell.md §6): x–x, x–G and G–G blocks are multiples of the
/// identity; rows and columns of `a` are zero ([decision] of §6: no inertia of `a`).
template <class Tri>
Eigen::Matrix<double, ShellElementGeometry<Tri>::num_dofs, ShellElementGeometry<Tri>::num_dofs> mass_matrix(
    const ShellElementGeometry<Tri>& geo, const ShellQuadrature<Tri>& rule, double density) {
  constexpr int N = Tri::num_nodes;
  constexpr int nd = ShellElementGeometry<Tri>::num_dofs;
  Eigen::Matrix<double, N, N> mxx = Eigen::Matrix<double, N, N>::Zero();
  Eigen::Matrix<double, N, N> mxg = mxx;
  Eigen::Matrix<double, N, N> mgg = mxx;
  const int nt = rule.thickness_size();
  for (int q = 0; q < rule.plane_size(); ++q) {
    const auto& phi = rule.phi[static_cast<std::size_t>(q)];
    const double h_hat = geo.h.dot(phi);
    const Eigen::Matrix<double, N, N> pp = phi * phi.transpose();
    for (int k = 0; k < nt; ++k) {
      const std::size_t ip = static_cast<std::size_t>(q * nt + k);
      const double s = 0.5 * h_hat * rule.thickness_points[static_cast<std::size_t>(k)];
      const double w = density * geo.dV[ip];
      mxx += w * pp;
      mxg += (w * s) * pp;
      mgg += (w * s * s) * pp;
    }
  }
  Eigen::Matrix<double, nd, nd> M = Eigen::Matrix<double, nd, nd>::Zero();
  for (int j = 0; j < N; ++j)
    for (int k = 0; k < N; ++k)
      for (int i = 0; i < 3; ++i) {
        M(dofs_per_node * j + i, dofs_per_node * k + i) = mxx(j, k);
        M(dofs_per_node * j + i, dofs_per_node * k + 3 + i) = mxg(j, k);
        M(dofs_per_node * j + 3 + i, dofs_per_node * k + i) = mxg(j, k);
        M(dofs_per_node * j + 3 + i, dofs_per_node * k + 3 + i) = mgg(j, k);
      }
  return M;
}

}  // namespace shellflow::shell
