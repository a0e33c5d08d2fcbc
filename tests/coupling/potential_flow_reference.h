#pragma once
// Independent reference for 3-D panel flutter: linearised (acoustic) supersonic potential flow above a rectangular
// plate set in an infinite rigid wall; the plate is the Ritz model of plate_flutter_reference.h (Eigen only,
// written for the tests; the bodies are in the .cpp).
//
// Flow: free stream U = M a in +x over the wall z = 0, gas in z > 0, density rho, sound speed a. The perturbation
// potential phi obeys (d_t + U d_x)^2 phi / a^2 = lap phi, the wall phi_z = (d_t + U d_x) w at z = 0, the pressure is
// p = -rho (d_t + U d_x) phi. For w = W exp(s t + i kx x + i ky y) with Re s > 0 the solution that decays in z goes
// as exp(-mu z):
//    p^ = P(s, kx, ky) w^,   P = rho (s + i U kx)^2 / mu,   mu = sqrt(kx^2 + ky^2 + (s + i U kx)^2 / a^2).
// For Re s = sigma > 0, mu^2 is never real and non-positive on real (kx, ky): its imaginary part vanishes only where
// Im s + U kx = 0, and there mu^2 = k^2 + sigma^2 / a^2 > 0. So the principal root is the decaying, analytic branch.
// Limits: s -> 0 with ky = 0 gives p = rho U^2 / beta w_x (Ackeret); M -> inf gives p = rho a (w_t + U w_x)
// (piston theory); in 2-D the first order in s gives f = -qA (w_x + g_D w_t), g_D = (M^2 - 2) / ((M^2 - 1) U).
//
// Generalised aerodynamic matrix (the load on the plate in +w is -p), modes phi_j(x, y) = X_m(x) Y_n(y):
//    A_ij(s) = ∫ phi_i p[phi_j] dA = 1/(4 pi^2) ∫∫ conj(X^_m Y^_n) P X^_m' Y^_n' dkx dky     (Parseval),
// F^(k) = ∫ f(x) exp(-i k x) dx. The transforms are analytic (beam functions are sums of exponentials). Y_n and Y_n'
// of the same parity about mid-span make conj(Y^_n) Y^_n' real and even in ky; of opposite parity, odd (A = 0).
// Both integrals are adaptive Gauss–Kronrod (7-15) with break points where mu^2 nearly vanishes (the traces of the
// Mach cone, where P has integrable 1/sqrt and log singularities as sigma -> 0).
// Flutter: det(s^2 M + K + A(s)) = 0 from a piston-theory root, by successive linearisation of A(s) about the current
// s (a quadratic eigenproblem per step, A' by the secant of the last two steps): a p-k iteration, to 1e-7 |s|.
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <functional>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "plate_flutter_reference.h"

namespace shellflow::testing::potential_reference {

using cplx = std::complex<double>;
using plate_reference::Edge;
using plate_reference::Plate;

/// Free stream: density (kg/m^3), sound speed (m/s), Mach number (> 1).
struct Flow {
  double rho = 0.339;
  double a = 340.0;
  double mach = 3.5;
  double U() const { return mach * a; }
};
inline Flow flow_from(double rho, double pressure, double gamma, double mach) {
  return {rho, std::sqrt(gamma * pressure / rho), mach};
}

namespace detail {

/// (e^w - 1) / w, by its series near w = 0.
cplx expm1_over(cplx w);

/// One mode on [0, L] as sum_j c_j exp(z_j (xi - xi0_j)), xi = x / L, xi0 in {0, 1} so that no term exceeds |c_j|.
class Mode1D {
 public:
  Mode1D(Edge edge, int index, double length);
  /// +1: even about mid-length, -1: odd.
  int parity() const { return parity_; }
  /// F^(k) = ∫_0^L f(x) e^{-i k x} dx.
  cplx transform(double k) const;

 private:
  struct Term {
    cplx c, z;
    int xi0;
  };
  std::vector<Term> terms_;
  double L_;
  int parity_;
};

/// Gauss–Kronrod 7-15 nodes and weights (QUADPACK's qk15).
inline constexpr std::array<double, 8> kronrod_x = {
    0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
    0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
    0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
    0.207784955007898467600689403773245, 0.0};
inline constexpr std::array<double, 8> kronrod_w = {
    0.022935322010529224963732008058970, 0.063092092629978553290700663189204, 0.104790010322250183839876322541518,
    0.140653259715525918745189590510238, 0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
    0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
inline constexpr std::array<double, 4> gauss_w = {
    0.129484966168869693270611432679082, 0.279705391489276667901467771423780, 0.381830050505118944950369775488975,
    0.417959183673469387755102040816327};

/// The 15 Kronrod nodes on [lo, hi]: centre, then c - h x_j, c + h x_j for j = 0..6.
std::array<double, 15> kronrod_nodes(double lo, double hi);

/// Global adaptive Gauss–Kronrod 7-15 of a vector-valued f over the pieces between consecutive sorted break points:
/// the piece with the largest |K15 - G7| (max norm) is halved until the sum of those is below
/// rel_tol |integral| (max norm) or max_pieces is reached.
template <class F>
Eigen::VectorXcd integrate(const F& f, std::vector<double> breaks, double rel_tol, int max_pieces = 20000);

/// Break points on [lo, hi]: every `spacing`, plus the given extra points inside.
std::vector<double> break_points(double lo, double hi, double spacing, const std::vector<double>& extra);

/// Values of a function of k that does not depend on s, kept at the Kronrod nodes of the regular pieces (the
/// adaptive quadrature asks for exactly these doubles on every piece it has not split).
class NodeCache {
 public:
  template <class G>
  NodeCache(const std::vector<double>& breaks, const G& g);
  /// The kept value at exactly k, or nullptr.
  const Eigen::VectorXcd* find(double k) const;

 private:
  struct Entry {
    double k;
    Eigen::VectorXcd value;
  };
  std::vector<Entry> entries_;
};

}  // namespace detail

/// Quadrature settings: wavenumbers up to cutoff / length in each direction; relative tolerance.
struct Accuracy {
  double cutoff = 150.0;
  double rel_tol = 1e-7;
};

/// The plate's aerodynamic matrices for a chosen set of its Ritz modes (indices k = (m-1) modes_y + (n-1) as in
/// plate_reference::assemble).
class Aerodynamics {
 public:
  Aerodynamics(const Plate& p, std::vector<int> modes, const Flow& flow, Accuracy acc = {});

  /// A(s) (N/m per unit generalised coordinate, ordered as `modes`), Re s > 0.
  Eigen::MatrixXcd matrix(cplx s) const;

  /// The 2-D limit: A per unit span of the x-modes alone (ky = 0, a plate of infinite span), nx x nx.
  Eigen::MatrixXcd matrix_2d(cplx s) const;

 private:
  /// (s + i U kx)^2: the factor of P that does not depend on ky.
  cplx pressure_factor(cplx s, double kx) const;

  static std::vector<detail::Mode1D> modes_1d(Edge edge, int count, double length);
  /// Regular break points every pi / length up to cutoff / length (ky >= 0: the integrand is even in ky).
  std::vector<double> x_breaks(const std::vector<double>& extra) const;
  std::vector<double> y_breaks(const std::vector<double>& extra) const;

  /// conj(X^_m) X^_m' at kx, as m nx + m'.
  Eigen::VectorXcd x_products(double kx) const;
  /// 2 Re(conj(Y^_n) Y^_n') at ky (the sum of ky and -ky), as n ny + n'; zero for opposite parities.
  Eigen::VectorXcd y_products(double ky) const;

  /// ∫ conj(Y^_n) Y^_n' / mu dky over all ky for all (n, n'), as a vector n ny + n'.
  Eigen::VectorXcd y_integral(cplx s, double kx) const;

  /// ∫ (s + i U kx)^2 conj(X^_m) X^_m' inner(kx) dkx for all (m, m') and inner components q, as (m nx + m') nq + q.
  template <class Inner>
  Eigen::VectorXcd outer_integral(cplx s, const Inner& inner, int nq) const;

  std::vector<int> modes_;
  Flow flow_;
  Accuracy acc_;
  double a_, b_;
  int my_;
  std::vector<detail::Mode1D> x_, y_;
  detail::NodeCache x_cache_, y_cache_;
};

/// Roots s of det(s^2 M + s B + C) = 0 (companion form; M symmetric positive definite).
Eigen::VectorXcd quadratic_roots(const Eigen::MatrixXd& M, const Eigen::MatrixXcd& B, const Eigen::MatrixXcd& C);

/// A flutter root: s (1/s) and the p-k iterations it took.
struct Root {
  cplx s;
  int iterations = 0;
};

/// The root of det(s^2 M + K + A(s)) = 0 nearest s0, by successive linearisation of A about the current s.
Root flutter_root(const Eigen::MatrixXd& M, const Eigen::MatrixXd& K, const std::function<Eigen::MatrixXcd(cplx)>& A,
                  cplx s0, double tol = 1e-7, int max_iterations = 30);

}  // namespace shellflow::testing::potential_reference
