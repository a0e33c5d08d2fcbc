#pragma once
// Independent reference model for the panel-flutter tests: linear flutter of a rectangular plate or of a shallow
// cylindrical panel under first-order piston theory, by Rayleigh–Ritz (Eigen 3.4 only; the bodies are in the .cpp).
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
void gauss_legendre(int n, Eigen::VectorXd& x, Eigen::VectorXd& w);

/// beta_m of the clamped–clamped beam: m-th positive root of cos(beta) cosh(beta) = 1 (4.7300, 7.8532, ...).
double clamped_beta(int m);

/// d^p/dxi^p (p = 0, 1, 2) of the clamped–clamped beam function on xi in [0, 1],
///   phi = cosh(b xi) - cos(b xi) - sigma (sinh(b xi) - sin(b xi)),  sigma = (cosh b - cos b) / (sinh b - sin b),
/// evaluated without cancellation as phi = (1+sigma)/2 e^{-b xi} + c1 e^{-b (1-xi)} - cos(b xi) + sigma sin(b xi),
/// c1 = (1-sigma)/2 e^b = (cos b - sin b - e^{-b}) / (1 - e^{-2b} - 2 sin b e^{-b}). Normalized: ∫ phi^2 dxi = 1.
struct BeamCoefficients {
  double sigma, c1;
};
BeamCoefficients clamped_beam_coefficients(double beta);
double clamped_beam(double beta, double xi, int p);

/// Values of n 1-D basis functions and their x-derivatives (orders 0..2, physical: d/dx = d/dxi / L) at the nodes.
struct Basis1D {
  Eigen::MatrixXd f[3];  ///< f[p](node, function)
  Basis1D(Edge edge, int n, double L, const Eigen::VectorXd& xi);
};

/// I_ij = ∫_0^L F^(p)_i G^(q)_j dx with quadrature weights wq (on [0, 1]).
Eigen::MatrixXd integral(const Basis1D& F, int p, const Basis1D& G, int q, const Eigen::VectorXd& wq, double L);

/// Kronecker product: (X ⊗ Y)(i ny + k, j my + l) = X(i, j) Y(k, l), i.e. the 2-D integral of separable products.
Eigen::MatrixXd kron(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y);

}  // namespace detail

/// Number of in-plane modes per direction actually used.
inline int inplane_modes(const Plate& p) {
  return p.inplane_modes > 0 ? p.inplane_modes : 2 * std::max(p.modes_x, p.modes_y);
}

/// Ritz matrices M, K (in-plane condensed), A1, A0 of the panel (see the file header for the equations).
Matrices assemble(const Plate& p);

/// In-vacuo natural frequencies (Hz), ascending: det(K - omega^2 M) = 0.
std::vector<double> natural_frequencies_hz(const Matrices& m);
inline std::vector<double> natural_frequencies_hz(const Plate& p) { return natural_frequencies_hz(assemble(p)); }

/// Stability of the panel at a given lambda. Non-dimensional form (tau = t / T, T = sqrt(rho h a^4 / D)):
///   Mn q'' + lambda gamma A0 q' + (Kn + lambda A1n) q = 0,  Mn = M/(rho h), Kn = K a^4/D, A1n = a A1,
///   gamma = g_D a / T;
/// with M = L L^T symmetrized as y'' + B y' + A y = 0, A = L^-1 (Kn + lambda A1n) L^-T, B = lambda gamma L^-1 A0 L^-T.
class FlutterProblem {
 public:
  FlutterProblem(const Plate& p, const Matrices& m, double g_D);

  struct Root {
    double growth = 0.0;        ///< max over the roots s of Re(s) / |s| (> 1e-8: unstable)
    double frequency_hz = 0.0;  ///< |Im s| / (2 pi T) of that root
  };

  /// The least stable root at lambda. Undamped (g_D = 0): eigenvalues mu = -s^2 of A, s = i sqrt(mu), so
  /// Re s / |s| = |Im sqrt(mu)| / |sqrt(mu)| (flutter: complex mu after a coalescence; divergence: mu < 0).
  /// Damped: eigenvalues of the state matrix [[0, W I], [-A/W, -B]] of z = (y, y'/W), W^2 = max_i A_ii (scaling).
  Root least_stable(double lambda) const;
  bool unstable(double lambda) const { return least_stable(lambda).growth > 1e-8; }

 private:
  Eigen::MatrixXd K_, A1_, A0_;
  double T_ = 1.0, gamma_ = 0.0;
};

/// Lowest lambda_cr = qA a^3 / D at which a root of det(s^2 M + s qA g_D A0 + K + qA A1) = 0 has Re s > 1e-8 |s|
/// (g_D = 0: the classical undamped coalescence, mu/M -> 0; g_D in s, see piston_theory). Scan, then bisection.
Flutter critical_lambda(const Plate& p, const Matrices& m, double g_D = 0.0, const ScanOptions& o = {});
inline Flutter critical_lambda(const Plate& p, double g_D = 0.0, const ScanOptions& o = {}) {
  return critical_lambda(p, assemble(p), g_D, o);
}

}  // namespace shellflow::testing::plate_reference
