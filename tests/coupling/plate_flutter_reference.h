#pragma once
// Independent reference model for the panel-flutter tests: linear flutter of a rectangular plate or of a shallow
// cylindrical panel under first-order piston theory, by Rayleigh–Ritz (Eigen 3.4 only, header-only).
//
// Geometry and units (SI): x in [0, a] is streamwise (flow in +x), y in [0, b] spanwise, w the deflection (m) towards
// the wetted (upper) side. Thickness h, Young's modulus E, Poisson ratio nu, density rho (kg/m^3),
// D = E h^3 / (12 (1 - nu^2)). Optional shallow cylindrical curvature with the cylinder axis along x: curvature 1/R in
// y (R = inf: flat). Donnell shallow-shell kinematics: eps_x = u_x, eps_y = v_y + w/R, gamma_xy = u_y + v_x, bending
// curvatures -w_xx, -w_yy, -2 w_xy. Strain energy
//   U = 1/2 ∫ [ C (eps_x^2 + eps_y^2 + 2 nu eps_x eps_y + (1-nu)/2 gamma^2)
//             + D (w_xx^2 + w_yy^2 + 2 nu w_xx w_yy + 2 (1-nu) w_xy^2) ] dA,   C = E h / (1 - nu^2);
// kinetic energy T = 1/2 ∫ rho h w_t^2 dA (in-plane inertia neglected: u, v are condensed statically,
// K = K_ww - K_wi K_ii^-1 K_iw).
//
// Edges: u = v = 0 on all four edges (immovable), u, v = sum sin(i pi x/a) sin(j pi y/b), i, j = 1..Nu. For w, each
// pair of opposite edges is simply supported (w = 0: sin(m pi x/a)) or clamped (w = w_n = 0: clamped–clamped
// Euler–Bernoulli beam eigenfunctions); w = sum q_k X_m(x) Y_n(y), k = (m-1) modes_y + (n-1).
//
// Aerodynamics (first-order piston theory, upper side): net load per area in +w
//   f = -qA (w_x + g_D w_t),  qA = rho_air U^2 / beta,  g_D = (M^2 - 2) / ((M^2 - 1) U)  [s],  beta = sqrt(M^2 - 1);
// Dowell's parameter lambda = qA a^3 / D (a streamwise). Equations of motion (generalized force Q_i = ∫ phi_i f dA):
//   M q'' + qA g_D A0 q' + (K + qA A1) q = 0,   A0_ij = ∫ phi_i phi_j dA,  A1_ij = ∫ phi_i d(phi_j)/dx dA.
// All 1-D integrals by Gauss–Legendre quadrature; 2-D integrals are products of 1-D ones (separable bases).
// Eigen included as a system header in the project build (imported CMake target); when compiled standalone with
// -I and -Werror, GCC 12 reports false -Wmaybe-uninitialized positives inside Eigen's products.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <Eigen/Dense>
#pragma GCC diagnostic pop

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace shellflow::testing::plate_reference {

enum class Edge { simply_supported, clamped };

/// Panel data (SI). Defaults: the aluminium test panel, 0.5 m square, simply supported, flat.
struct Plate {
  double a = 0.5;       ///< streamwise length (m)
  double b = 0.5;       ///< spanwise width (m)
  double h = 1.35e-3;   ///< thickness (m)
  double E = 77.28e9;   ///< Young's modulus (Pa)
  double nu = 0.33;     ///< Poisson ratio
  double rho = 2710.0;  ///< density (kg/m^3)
  /// radius of the cylinder (axis along x), m; inf = flat
  double R = std::numeric_limits<double>::infinity();
  Edge x_edges = Edge::simply_supported;  ///< edges x = 0 and x = a
  Edge y_edges = Edge::simply_supported;  ///< edges y = 0 and y = b
  int modes_x = 6;                        ///< w modes in x
  int modes_y = 3;                        ///< w modes in y
  int inplane_modes = 0;                  ///< Nu per direction for u and v each; 0 = 2 max(modes_x, modes_y)
  int quad_points = 0;  ///< Gauss points per direction; 0 = 2 max(modes_x, modes_y, Nu if curved) + 20
};

/// Ritz matrices in the w-mode basis (in-plane dofs condensed). M in kg, K in N/m, A1 in m, A0 in m^2.
struct Matrices {
  Eigen::MatrixXd M, K, A1, A0;
};

/// Flutter point: lambda_cr = qA a^3 / D and the frequency of the destabilized root there (Hz). NaN if none found.
struct Flutter {
  double lambda_cr = std::numeric_limits<double>::quiet_NaN();
  double frequency_hz = std::numeric_limits<double>::quiet_NaN();
};

/// lambda scan: stability checked at lambda = k lambda_step up to lambda_max, then bisection to rel_tol.
struct ScanOptions {
  double lambda_max = 5000.0;
  double lambda_step = 5.0;
  double rel_tol = 1e-9;
};

/// Piston-theory coefficients of the load f = -qA (w_x + g_D w_t).
struct PistonTheory {
  double qA;   ///< rho U^2 / sqrt(M^2 - 1), Pa
  double g_D;  ///< (M^2 - 2) / ((M^2 - 1) U), s
};

/// D = E h^3 / (12 (1 - nu^2)) in N m.
inline double flexural_rigidity(const Plate& p) { return p.E * p.h * p.h * p.h / (12.0 * (1.0 - p.nu * p.nu)); }

/// qA and g_D of first-order piston theory for air density rho_air (kg/m^3), speed U (m/s), Mach number mach > 1.
inline PistonTheory piston_theory(double rho_air, double U, double mach) {
  const double m2 = mach * mach;
  return {rho_air * U * U / std::sqrt(m2 - 1.0), (m2 - 2.0) / ((m2 - 1.0) * U)};
}

/// Non-dimensional frequency omega a^2 sqrt(rho h / D) of a frequency f_hz (Leissa's parameter, a streamwise).
inline double frequency_parameter(const Plate& p, double f_hz) {
  return 2.0 * std::numbers::pi * f_hz * p.a * p.a * std::sqrt(p.rho * p.h / flexural_rigidity(p));
}

namespace detail {

/// Gauss–Legendre nodes x and weights w on [0, 1] (Newton on P_n; exact for polynomials of degree 2n - 1).
inline void gauss_legendre(int n, Eigen::VectorXd& x, Eigen::VectorXd& w) {
  x.resize(n);
  w.resize(n);
  for (int i = 0; i < (n + 1) / 2; ++i) {
    double z = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5)), dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p1 = 1.0, p2 = 0.0;
      for (int j = 1; j <= n; ++j) {
        const double p3 = p2;
        p2 = p1;
        p1 = ((2.0 * j - 1.0) * z * p2 - (j - 1.0) * p3) / j;
      }
      dp = n * (z * p1 - p2) / (z * z - 1.0);
      const double dz = p1 / dp;
      z -= dz;
      if (std::abs(dz) < 1e-16) break;
    }
    x(i) = 0.5 * (1.0 - z);
    x(n - 1 - i) = 0.5 * (1.0 + z);
    w(i) = w(n - 1 - i) = 1.0 / ((1.0 - z * z) * dp * dp);
  }
}

/// beta_m of the clamped–clamped beam: m-th positive root of cos(beta) cosh(beta) = 1 (4.7300, 7.8532, ...).
inline double clamped_beta(int m) {
  double beta = (2.0 * m + 1.0) * std::numbers::pi / 2.0;
  for (int it = 0; it < 60; ++it) {
    const double f = std::cos(beta) - 1.0 / std::cosh(beta);
    const double df = -std::sin(beta) + std::tanh(beta) / std::cosh(beta);
    const double d = f / df;
    beta -= d;
    if (std::abs(d) < 1e-15 * beta) break;
  }
  return beta;
}

/// d^p/dxi^p (p = 0, 1, 2) of the clamped–clamped beam function on xi in [0, 1],
///   phi = cosh(b xi) - cos(b xi) - sigma (sinh(b xi) - sin(b xi)),  sigma = (cosh b - cos b) / (sinh b - sin b),
/// evaluated without cancellation as phi = (1+sigma)/2 e^{-b xi} + c1 e^{-b (1-xi)} - cos(b xi) + sigma sin(b xi),
/// c1 = (1-sigma)/2 e^b = (cos b - sin b - e^{-b}) / (1 - e^{-2b} - 2 sin b e^{-b}). Normalized: ∫ phi^2 dxi = 1.
struct BeamCoefficients {
  double sigma, c1;
};
inline BeamCoefficients clamped_beam_coefficients(double beta) {
  const double eb = std::exp(-beta), s = std::sin(beta), c = std::cos(beta);
  const double den = 1.0 - eb * eb - 2.0 * s * eb;
  return {(1.0 + eb * eb - 2.0 * c * eb) / den, (c - s - eb) / den};
}
inline double clamped_beam(double beta, double xi, int p) {
  const auto [sigma, c1] = clamped_beam_coefficients(beta);
  const double e1 = 0.5 * (1.0 + sigma) * std::exp(-beta * xi), e2 = c1 * std::exp(-beta * (1.0 - xi));
  const double cx = std::cos(beta * xi), sx = std::sin(beta * xi);
  if (p == 0) return e1 + e2 - cx + sigma * sx;
  if (p == 1) return beta * (-e1 + e2 + sx + sigma * cx);
  return beta * beta * (e1 + e2 + cx - sigma * sx);
}

/// Values of n 1-D basis functions and their x-derivatives (orders 0..2, physical: d/dx = d/dxi / L) at the nodes.
struct Basis1D {
  Eigen::MatrixXd f[3];  ///< f[p](node, function)
  Basis1D(Edge edge, int n, double L, const Eigen::VectorXd& xi) {
    for (auto& m : f) m.resize(xi.size(), n);
    for (int k = 0; k < n; ++k) {
      const double beta = edge == Edge::clamped ? clamped_beta(k + 1) : (k + 1) * std::numbers::pi;
      for (int i = 0; i < xi.size(); ++i)
        for (int p = 0; p < 3; ++p) {
          double v = 0.0;
          if (edge == Edge::clamped) {
            v = clamped_beam(beta, xi(i), p);
          } else {
            const double sn = std::sin(beta * xi(i)), cs = std::cos(beta * xi(i));
            v = p == 0 ? sn : p == 1 ? beta * cs : -beta * beta * sn;
          }
          f[p](i, k) = v / std::pow(L, p);
        }
    }
  }
};

/// I_ij = ∫_0^L F^(p)_i G^(q)_j dx with quadrature weights wq (on [0, 1]).
inline Eigen::MatrixXd integral(const Basis1D& F, int p, const Basis1D& G, int q, const Eigen::VectorXd& wq, double L) {
  return F.f[p].transpose() * (L * wq).asDiagonal() * G.f[q];
}

/// Kronecker product: (X ⊗ Y)(i ny + k, j my + l) = X(i, j) Y(k, l), i.e. the 2-D integral of separable products.
inline Eigen::MatrixXd kron(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y) {
  Eigen::MatrixXd Z(X.rows() * Y.rows(), X.cols() * Y.cols());
  for (Eigen::Index i = 0; i < X.rows(); ++i)
    for (Eigen::Index j = 0; j < X.cols(); ++j) Z.block(i * Y.rows(), j * Y.cols(), Y.rows(), Y.cols()) = X(i, j) * Y;
  return Z;
}

}  // namespace detail

/// Number of in-plane modes per direction actually used.
inline int inplane_modes(const Plate& p) {
  return p.inplane_modes > 0 ? p.inplane_modes : 2 * std::max(p.modes_x, p.modes_y);
}

/// Ritz matrices M, K (in-plane condensed), A1, A0 of the panel (see the file header for the equations).
inline Matrices assemble(const Plate& p) {
  using detail::integral, detail::kron;
  const bool curved = std::isfinite(p.R);
  const int nu_modes = inplane_modes(p);
  const int nq = p.quad_points > 0 ? p.quad_points : 2 * std::max({p.modes_x, p.modes_y, curved ? nu_modes : 0}) + 20;
  Eigen::VectorXd xi, wq;
  detail::gauss_legendre(nq, xi, wq);
  const detail::Basis1D wx(p.x_edges, p.modes_x, p.a, xi), wy(p.y_edges, p.modes_y, p.b, xi);
  const auto Wx = [&](int i, int j) { return integral(wx, i, wx, j, wq, p.a); };
  const auto Wy = [&](int i, int j) { return integral(wy, i, wy, j, wq, p.b); };
  const double D = flexural_rigidity(p), nu = p.nu;

  Matrices m;
  m.A0 = kron(Wx(0, 0), Wy(0, 0));
  m.M = p.rho * p.h * m.A0;
  m.A1 = kron(Wx(0, 1), Wy(0, 0));
  m.K = D * (kron(Wx(2, 2), Wy(0, 0)) + kron(Wx(0, 0), Wy(2, 2)) +
             nu * (kron(Wx(2, 0), Wy(0, 2)) + kron(Wx(0, 2), Wy(2, 0))) + 2.0 * (1.0 - nu) * kron(Wx(1, 1), Wy(1, 1)));
  if (!curved) return m;  // flat: the membrane does not couple to w (linear theory)

  // Membrane energy with eps_y = v_y + k w, k = 1/R: K_ww += C k^2 ∫ w w, K_uw = C nu k ∫ u_x w, K_vw = C k ∫ v_y w.
  const double C = p.E * p.h / (1.0 - nu * nu), k = 1.0 / p.R, g = 0.5 * (1.0 - nu);
  const detail::Basis1D sx(Edge::simply_supported, nu_modes, p.a, xi), sy(Edge::simply_supported, nu_modes, p.b, xi);
  const auto Sx = [&](int i, int j) { return integral(sx, i, sx, j, wq, p.a); };
  const auto Sy = [&](int i, int j) { return integral(sy, i, sy, j, wq, p.b); };
  const Eigen::MatrixXd Sx00 = Sx(0, 0), Sx11 = Sx(1, 1), Sy00 = Sy(0, 0), Sy11 = Sy(1, 1);
  const Eigen::Index ni = Eigen::Index(nu_modes) * nu_modes, nw = m.K.rows();
  Eigen::MatrixXd Kii(2 * ni, 2 * ni), Kiw(2 * ni, nw);
  Kii.topLeftCorner(ni, ni) = C * (kron(Sx11, Sy00) + g * kron(Sx00, Sy11));      // u_x^2 + (1-nu)/2 u_y^2
  Kii.bottomRightCorner(ni, ni) = C * (kron(Sx00, Sy11) + g * kron(Sx11, Sy00));  // v_y^2 + (1-nu)/2 v_x^2
  Kii.topRightCorner(ni, ni) = C * (nu * kron(Sx(1, 0), Sy(0, 1)) + g * kron(Sx(0, 1), Sy(1, 0)));  // u_x v_y, u_y v_x
  Kii.bottomLeftCorner(ni, ni) = Kii.topRightCorner(ni, ni).transpose();
  Kiw.topRows(ni) = C * nu * k * kron(integral(sx, 1, wx, 0, wq, p.a), integral(sy, 0, wy, 0, wq, p.b));
  Kiw.bottomRows(ni) = C * k * kron(integral(sx, 0, wx, 0, wq, p.a), integral(sy, 1, wy, 0, wq, p.b));
  const Eigen::LLT<Eigen::MatrixXd> llt(Kii);
  if (llt.info() != Eigen::Success) throw std::runtime_error("plate_reference: in-plane stiffness not positive");
  m.K += C * k * k * m.A0 - Kiw.transpose() * llt.solve(Kiw);
  m.K = 0.5 * (m.K + m.K.transpose());  // remove the round-off asymmetry of the condensation
  return m;
}

/// In-vacuo natural frequencies (Hz), ascending: det(K - omega^2 M) = 0.
inline std::vector<double> natural_frequencies_hz(const Matrices& m) {
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(m.K, m.M, Eigen::EigenvaluesOnly);
  std::vector<double> f;
  for (Eigen::Index i = 0; i < es.eigenvalues().size(); ++i)
    f.push_back(std::sqrt(std::max(0.0, es.eigenvalues()(i))) / (2.0 * std::numbers::pi));
  return f;
}
inline std::vector<double> natural_frequencies_hz(const Plate& p) { return natural_frequencies_hz(assemble(p)); }

/// Stability of the panel at a given lambda. Non-dimensional form (tau = t / T, T = sqrt(rho h a^4 / D)):
///   Mn q'' + lambda gamma A0 q' + (Kn + lambda A1n) q = 0,  Mn = M/(rho h), Kn = K a^4/D, A1n = a A1,
///   gamma = g_D a / T;
/// with M = L L^T symmetrized as y'' + B y' + A y = 0, A = L^-1 (Kn + lambda A1n) L^-T, B = lambda gamma L^-1 A0 L^-T.
class FlutterProblem {
 public:
  FlutterProblem(const Plate& p, const Matrices& m, double g_D) {
    const double D = flexural_rigidity(p);
    T_ = std::sqrt(p.rho * p.h * std::pow(p.a, 4) / D);
    gamma_ = g_D * p.a / T_;
    const Eigen::LLT<Eigen::MatrixXd> llt(m.M / (p.rho * p.h));
    if (llt.info() != Eigen::Success) throw std::runtime_error("plate_reference: mass matrix not positive");
    const auto sym = [&](const Eigen::MatrixXd& X) {
      const Eigen::MatrixXd Y = llt.matrixL().solve(X);
      return Eigen::MatrixXd(llt.matrixL().solve(Y.transpose()).transpose());
    };
    K_ = sym(m.K * std::pow(p.a, 4) / D);
    A1_ = sym(m.A1 * p.a);
    A0_ = sym(m.A0);
  }

  struct Root {
    double growth = 0.0;        ///< max over the roots s of Re(s) / |s| (> 1e-8: unstable)
    double frequency_hz = 0.0;  ///< |Im s| / (2 pi T) of that root
  };

  /// The least stable root at lambda. Undamped (g_D = 0): eigenvalues mu = -s^2 of A, s = i sqrt(mu), so
  /// Re s / |s| = |Im sqrt(mu)| / |sqrt(mu)| (flutter: complex mu after a coalescence; divergence: mu < 0).
  /// Damped: eigenvalues of the state matrix [[0, W I], [-A/W, -B]] of z = (y, y'/W), W^2 = max_i A_ii (scaling).
  Root least_stable(double lambda) const {
    const Eigen::MatrixXd A = K_ + lambda * A1_;
    const Eigen::Index n = A.rows();
    Root r{-std::numeric_limits<double>::infinity(), 0.0};
    if (gamma_ == 0.0) {
      const Eigen::EigenSolver<Eigen::MatrixXd> es(A, false);
      for (Eigen::Index i = 0; i < n; ++i) {
        const std::complex<double> sq = std::sqrt(es.eigenvalues()(i));
        const double g = std::abs(sq.imag()) / std::abs(sq);
        if (g > r.growth) r = {g, std::abs(sq.real()) / (2.0 * std::numbers::pi * T_)};
      }
      return r;
    }
    const double W = std::sqrt(A.diagonal().maxCoeff());
    Eigen::MatrixXd S = Eigen::MatrixXd::Zero(2 * n, 2 * n);
    S.topRightCorner(n, n).diagonal().setConstant(W);
    S.bottomLeftCorner(n, n) = -A / W;
    S.bottomRightCorner(n, n) = -lambda * gamma_ * A0_;
    const Eigen::EigenSolver<Eigen::MatrixXd> es(S, false);
    for (Eigen::Index i = 0; i < 2 * n; ++i) {
      const std::complex<double> s = es.eigenvalues()(i);
      const double g = s.real() / std::abs(s);
      if (g > r.growth) r = {g, std::abs(s.imag()) / (2.0 * std::numbers::pi * T_)};
    }
    return r;
  }
  bool unstable(double lambda) const { return least_stable(lambda).growth > 1e-8; }

 private:
  Eigen::MatrixXd K_, A1_, A0_;
  double T_ = 1.0, gamma_ = 0.0;
};

/// Lowest lambda_cr = qA a^3 / D at which a root of det(s^2 M + s qA g_D A0 + K + qA A1) = 0 has Re s > 1e-8 |s|
/// (g_D = 0: the classical undamped coalescence, mu/M -> 0; g_D in s, see piston_theory). Scan, then bisection.
inline Flutter critical_lambda(const Plate& p, const Matrices& m, double g_D = 0.0, const ScanOptions& o = {}) {
  const FlutterProblem fp(p, m, g_D);
  double lo = 0.0, hi = std::numeric_limits<double>::quiet_NaN();
  for (int k = 1; k * o.lambda_step <= o.lambda_max * (1.0 + 1e-12); ++k) {
    if (fp.unstable(k * o.lambda_step)) {
      hi = k * o.lambda_step;
      break;
    }
    lo = k * o.lambda_step;
  }
  if (std::isnan(hi)) return {};
  while (hi - lo > o.rel_tol * hi) {
    const double mid = 0.5 * (lo + hi);
    (fp.unstable(mid) ? hi : lo) = mid;
  }
  return {0.5 * (lo + hi), fp.least_stable(hi).frequency_hz};
}
inline Flutter critical_lambda(const Plate& p, double g_D = 0.0, const ScanOptions& o = {}) {
  return critical_lambda(p, assemble(p), g_D, o);
}

}  // namespace shellflow::testing::plate_reference
