#pragma once
// Element kernel of the 7-parameter positional shell (shell.md §1–§6): strain energy,
// internal force, consistent tangent and constant mass of one curved triangle. It knows
// nothing of assembly, supports or time stepping.
//
// Unknowns of one element, node-major, 7 per node (shell.md §2.5, increment form):
//   u_e = [dx_0 (3), dG_0 (3), a_0 | dx_1 ... ],  dx = x - X, dG = G - V, a.
// `Tri` is fem::Tri3, fem::Tri6 or fem::Tri10 (Gmsh node order).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Dense>

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

  std::vector<double> plane_weights;  ///< sum to 1/2 (reference triangle area)
  std::vector<Values> phi;            ///< phi[q](j)
  std::vector<Gradients> dphi;        ///< dphi[q](j, alpha) = dphi_j / dxi_alpha
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
  void interpolate(const ShellElementGeometry<Tri>& geo,
                   const Eigen::Matrix<double, N, 1>& phi, const Eigen::Matrix<double, N, 2>& dphi,
                   const Vector& u) {
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
double max_abs_strain(const ShellElementGeometry<Tri>& geo, const ShellQuadrature<Tri>& rule,
                      const Vector& u) {
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
template <class Tri, class Vector>
bool internal_force(const ShellElementGeometry<Tri>& geo, const ShellQuadrature<Tri>& rule,
                    const SvkMaterial& material, const Vector& u,
                    Eigen::Matrix<double, ShellElementGeometry<Tri>::num_dofs, 1>& f,
                    Eigen::Matrix<double, ShellElementGeometry<Tri>::num_dofs,
                                  ShellElementGeometry<Tri>::num_dofs>* K) {
  constexpr int N = Tri::num_nodes;
  constexpr int nd = ShellElementGeometry<Tri>::num_dofs;
  const double lambda = material.lame_lambda();
  const double mu = material.lame_mu();
  Eigen::Matrix<double, 6, 6> C = Eigen::Matrix<double, 6, 6>::Zero();
  C.topLeftCorner<3, 3>().setConstant(lambda);
  C.diagonal().head<3>().array() += 2.0 * mu;
  C.diagonal().tail<3>().setConstant(mu);

  // Cholesky factor of the Voigt elasticity matrix: B^T C B = (L^T B)^T (L^T B), so the
  // material part is a symmetric rank-6 update of the lower triangle.
  const Eigen::Matrix<double, 6, 6> Lt = C.llt().matrixU();

  // Per volume point. Strain variations E_r (Voigt, engineering shear). For x and G dofs
  // D_r = dA1/dy_r A0^-1 = e_i d^T (one non-zero row), so the initial-stress term
  // (D_r S) : D_s = delta_il d_r^T S d_s works on node vectors; only `a` dofs need full D_r.
  Eigen::Matrix<double, 6, nd> Bv;
  Eigen::Matrix<double, 3, 2 * N> W;  // columns d_x(j), then d_G(j)
  std::array<Mat3, N> D_a;

  f.setZero();
  if (K) K->setZero();
  const int nt = rule.thickness_size();
  bool admissible = true;
  detail::PlanePoint<N> p;
  for (int q = 0; q < rule.plane_size(); ++q) {
    const auto& phi = rule.phi[static_cast<std::size_t>(q)];
    const auto& dphi = rule.dphi[static_cast<std::size_t>(q)];
    p.interpolate(geo, phi, dphi, u);
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

      const auto set_strain_column = [&](int col, const Mat3& M) {  // M = A^T D_r
        Bv(0, col) = M(0, 0);
        Bv(1, col) = M(1, 1);
        Bv(2, col) = M(2, 2);
        Bv(3, col) = M(0, 1) + M(1, 0);
        Bv(4, col) = M(1, 2) + M(2, 1);
        Bv(5, col) = M(0, 2) + M(2, 0);
      };
      for (int j = 0; j < N; ++j) {
        // dA1/dx_{j,i} = e_i c_x^T, dA1/dG_{j,i} = e_i c_G^T (rows of a 3x3, shell.md §4).
        const Vec3 c_x(dphi(j, 0), dphi(j, 1), 0.0);
        Vec3 c_G;
        for (int al = 0; al < 2; ++al)
          c_G(al) = 0.5 * (p.h_d[al] * zeta + p.h * zeta_d[al]) * phi(j) + 0.5 * p.h * zeta * dphi(j, al);
        c_G(2) = 0.5 * p.h * (1.0 + 2.0 * p.a * xi3) * phi(j);
        W.col(j) = A0i.transpose() * c_x;
        W.col(N + j) = A0i.transpose() * c_G;
        Mat3 dA1_a;
        for (int al = 0; al < 2; ++al)
          dA1_a.col(al) = 0.5 * xi3_sq * ((p.h_d[al] * phi(j) + p.h * dphi(j, al)) * p.g + p.h * phi(j) * p.g_d[al]);
        dA1_a.col(2) = p.h * xi3 * phi(j) * p.g;
        D_a[static_cast<std::size_t>(j)] = dA1_a * A0i;
        for (int i = 0; i < 3; ++i) {
          // A^T (e_i d^T) = (row i of A)^T d^T
          set_strain_column(dofs_per_node * j + i, A.row(i).transpose() * W.col(j).transpose());
          set_strain_column(dofs_per_node * j + 3 + i, A.row(i).transpose() * W.col(N + j).transpose());
        }
        set_strain_column(dofs_per_node * j + 6, A.transpose() * D_a[static_cast<std::size_t>(j)]);
      }
      Eigen::Matrix<double, 6, 1> S_voigt;
      S_voigt << S(0, 0), S(1, 1), S(2, 2), S(0, 1), S(1, 2), S(0, 2);
      f.noalias() += dV * (Bv.transpose() * S_voigt);
      if (!K) continue;

      // Material part, lower triangle only (symmetrised at the end).
      const Eigen::Matrix<double, 6, nd> LB = std::sqrt(dV) * (Lt * Bv);
      K->template selfadjointView<Eigen::Lower>().rankUpdate(LB.transpose());
      // Initial-stress part: x/G dofs through node vectors (3x3 identity blocks).
      const Eigen::Matrix<double, 2 * N, 2 * N> P = dV * (W.transpose() * (S * W));
      for (int j = 0; j < N; ++j)
        for (int kk = 0; kk < N; ++kk)
          for (int t = 0; t < 2; ++t)
            for (int t2 = 0; t2 < 2; ++t2) {
              const double v = P(t * N + j, t2 * N + kk);
              for (int i = 0; i < 3; ++i) (*K)(dofs_per_node * j + 3 * t + i, dofs_per_node * kk + 3 * t2 + i) += v;
            }
      // Initial-stress part with `a` dofs, plus the a–G term B : d2A1/(da_j dG_{k,i}),
      // B = A S A0^-T, where only row i of d2A1 is non-zero. Written to both triangles.
      const Mat3 B = A * S * A0i.transpose();
      for (int j = 0; j < N; ++j) {
        const int ra = dofs_per_node * j + 6;
        const Mat3 DaS = dV * (D_a[static_cast<std::size_t>(j)] * S);
        for (int kk = 0; kk < N; ++kk) {
          const Vec3 with_x = DaS * W.col(kk);
          const Vec3 with_G = DaS * W.col(N + kk);
          Vec3 c2;
          for (int al = 0; al < 2; ++al)
            c2(al) = 0.5 * xi3_sq * ((p.h_d[al] * phi(j) + p.h * dphi(j, al)) * phi(kk) + p.h * phi(j) * dphi(kk, al));
          c2(2) = p.h * xi3 * phi(j) * phi(kk);
          const Vec3 Bc = dV * (B * c2);
          for (int i = 0; i < 3; ++i) {
            const int sx = dofs_per_node * kk + i;
            const int sG = sx + 3;
            (*K)(ra, sx) += with_x(i);
            (*K)(sx, ra) += with_x(i);
            (*K)(ra, sG) += with_G(i) + Bc(i);
            (*K)(sG, ra) += with_G(i) + Bc(i);
          }
          (*K)(ra, dofs_per_node * kk + 6) += (DaS.array() * D_a[static_cast<std::size_t>(kk)].array()).sum();
        }
      }
    }
  }
  if (K)
    for (int c = 1; c < nd; ++c)
      for (int r = 0; r < c; ++r) (*K)(r, c) = (*K)(c, r);
  return admissible;
}

/// Constant consistent mass (shell.md §6): x–x, x–G and G–G blocks are multiples of the
/// identity; rows and columns of `a` are zero ([decision] of §6: no inertia of `a`).
template <class Tri>
Eigen::Matrix<double, ShellElementGeometry<Tri>::num_dofs, ShellElementGeometry<Tri>::num_dofs>
mass_matrix(const ShellElementGeometry<Tri>& geo, const ShellQuadrature<Tri>& rule, double density) {
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
