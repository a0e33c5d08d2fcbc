#pragma once
// Independent reference for 3-D panel flutter: linearised (acoustic) supersonic potential flow above a rectangular
// plate set in an infinite rigid wall; the plate is the Ritz model of plate_flutter_reference.h (Eigen only,
// header-only, written for the tests).
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
inline cplx expm1_over(cplx w) {
  if (std::abs(w) < 1e-2) return 1.0 + w * (1.0 / 2 + w * (1.0 / 6 + w * (1.0 / 24 + w * (1.0 / 120 + w / 720.0))));
  return (std::exp(w) - 1.0) / w;
}

/// One mode on [0, L] as sum_j c_j exp(z_j (xi - xi0_j)), xi = x / L, xi0 in {0, 1} so that no term exceeds |c_j|.
class Mode1D {
 public:
  Mode1D(Edge edge, int index, double length) : L_(length), parity_(index % 2 == 1 ? 1 : -1) {
    const cplx i(0.0, 1.0);
    if (edge == Edge::simply_supported) {  // sin(beta xi) = (e^{i beta xi} - e^{-i beta xi}) / 2i
      const double beta = index * std::numbers::pi;
      terms_ = {{-0.5 * i, i * beta, 0}, {0.5 * i, -i * beta, 0}};
      return;
    }
    // clamped_beam of plate_flutter_reference.h: 0.5 (1 + sigma) e^{-beta xi} + c1 e^{beta (xi - 1)} - cos + sigma sin
    const double beta = plate_reference::detail::clamped_beta(index);
    const auto [sigma, c1] = plate_reference::detail::clamped_beam_coefficients(beta);
    terms_ = {{0.5 * (1.0 + sigma), -beta, 0},
              {c1, beta, 1},
              {-0.5 - 0.5 * i * sigma, i * beta, 0},
              {-0.5 + 0.5 * i * sigma, -i * beta, 0}};
  }
  /// +1: even about mid-length, -1: odd.
  int parity() const { return parity_; }
  /// F^(k) = ∫_0^L f(x) e^{-i k x} dx.
  cplx transform(double k) const {
    const double kappa = k * L_;
    cplx sum = 0.0;
    for (const Term& t : terms_) {
      const cplx w = t.z - cplx(0.0, kappa);
      sum += t.xi0 == 0 ? t.c * expm1_over(w) : t.c * std::exp(cplx(0.0, -kappa)) * expm1_over(-w);
    }
    return L_ * sum;
  }

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
inline std::array<double, 15> kronrod_nodes(double lo, double hi) {
  const double c = 0.5 * (lo + hi), h = 0.5 * (hi - lo);
  std::array<double, 15> x{};
  x[0] = c;
  for (int j = 0; j < 7; ++j) {
    x[1 + 2 * j] = c - h * kronrod_x[j];
    x[2 + 2 * j] = c + h * kronrod_x[j];
  }
  return x;
}

/// Global adaptive Gauss–Kronrod 7-15 of a vector-valued f over the pieces between consecutive sorted break points:
/// the piece with the largest |K15 - G7| (max norm) is halved until the sum of those is below
/// rel_tol |integral| (max norm) or max_pieces is reached.
template <class F>
Eigen::VectorXcd integrate(const F& f, std::vector<double> breaks, double rel_tol, int max_pieces = 20000) {
  const auto& wk = kronrod_w;
  const auto& wg = gauss_w;
  struct Piece {
    double lo, hi;
    Eigen::VectorXcd value;
    double error;
  };
  const auto rule = [&](double lo, double hi) {
    const double h = 0.5 * (hi - lo);
    const std::array<double, 15> x = kronrod_nodes(lo, hi);
    Eigen::VectorXcd fc = f(x[0]);
    Eigen::VectorXcd k = wk[7] * fc, g = wg[3] * fc;
    for (int j = 0; j < 7; ++j) {
      const Eigen::VectorXcd sum = f(x[1 + 2 * j]) + f(x[2 + 2 * j]);
      k += wk[j] * sum;
      if (j % 2 == 1) g += wg[j / 2] * sum;
    }
    return Piece{lo, hi, h * k, h * (k - g).cwiseAbs().maxCoeff()};
  };
  std::sort(breaks.begin(), breaks.end());
  breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());
  std::vector<Piece> pieces;
  for (std::size_t j = 0; j + 1 < breaks.size(); ++j) pieces.push_back(rule(breaks[j], breaks[j + 1]));
  while (true) {
    Eigen::VectorXcd total = Eigen::VectorXcd::Zero(pieces.front().value.size());
    double error = 0.0;
    std::size_t worst = 0;
    for (std::size_t j = 0; j < pieces.size(); ++j) {
      total += pieces[j].value;
      error += pieces[j].error;
      if (pieces[j].error > pieces[worst].error) worst = j;
    }
    if (error <= rel_tol * total.cwiseAbs().maxCoeff()) return total;
    if (static_cast<int>(pieces.size()) >= max_pieces)
      throw std::runtime_error("potential_reference: adaptive quadrature did not converge");
    const Piece w = pieces[worst];
    const double mid = 0.5 * (w.lo + w.hi);
    pieces[worst] = rule(w.lo, mid);
    pieces.push_back(rule(mid, w.hi));
  }
}

/// Break points on [lo, hi]: every `spacing`, plus the given extra points inside.
inline std::vector<double> break_points(double lo, double hi, double spacing, const std::vector<double>& extra) {
  std::vector<double> b;
  const int n = static_cast<int>(std::ceil((hi - lo) / spacing));
  for (int j = 0; j <= n; ++j) b.push_back(lo + (hi - lo) * j / n);
  for (const double e : extra)
    if (e > lo && e < hi) b.push_back(e);
  return b;
}

/// Values of a function of k that does not depend on s, kept at the Kronrod nodes of the regular pieces (the
/// adaptive quadrature asks for exactly these doubles on every piece it has not split).
class NodeCache {
 public:
  template <class G>
  NodeCache(const std::vector<double>& breaks, const G& g) {
    for (std::size_t j = 0; j + 1 < breaks.size(); ++j)
      for (const double x : kronrod_nodes(breaks[j], breaks[j + 1])) entries_.push_back({x, g(x)});
    std::sort(entries_.begin(), entries_.end(), [](const auto& l, const auto& r) { return l.k < r.k; });
  }
  /// The kept value at exactly k, or nullptr.
  const Eigen::VectorXcd* find(double k) const {
    const auto it =
        std::lower_bound(entries_.begin(), entries_.end(), k, [](const auto& e, double x) { return e.k < x; });
    return it != entries_.end() && it->k == k ? &it->value : nullptr;
  }

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
  Aerodynamics(const Plate& p, std::vector<int> modes, const Flow& flow, Accuracy acc = {})
      : modes_(std::move(modes)),
        flow_(flow),
        acc_(acc),
        a_(p.a),
        b_(p.b),
        my_(p.modes_y),
        x_(modes_1d(p.x_edges, p.modes_x, p.a)),
        y_(modes_1d(p.y_edges, p.modes_y, p.b)),
        x_cache_(x_breaks({}), [&](double kx) { return x_products(kx); }),
        y_cache_(y_breaks({}), [&](double ky) { return y_products(ky); }) {}

  /// A(s) (N/m per unit generalised coordinate, ordered as `modes`), Re s > 0.
  Eigen::MatrixXcd matrix(cplx s) const {
    if (!(s.real() > 0.0)) throw std::invalid_argument("potential_reference: A(s) needs Re s > 0");
    const int nx = static_cast<int>(x_.size()), ny = static_cast<int>(y_.size());
    const auto inner = [&](double kx) { return y_integral(s, kx); };
    const Eigen::VectorXcd I = outer_integral(s, inner, ny * ny);
    Eigen::MatrixXcd A(modes_.size(), modes_.size());
    for (std::size_t i = 0; i < modes_.size(); ++i)
      for (std::size_t j = 0; j < modes_.size(); ++j) {
        const int m = modes_[i] / my_, n = modes_[i] % my_, mp = modes_[j] / my_, np = modes_[j] % my_;
        A(i, j) = flow_.rho / (4.0 * std::numbers::pi * std::numbers::pi) * I((m * nx + mp) * ny * ny + n * ny + np);
      }
    return A;
  }

  /// The 2-D limit: A per unit span of the x-modes alone (ky = 0, a plate of infinite span), nx x nx.
  Eigen::MatrixXcd matrix_2d(cplx s) const {
    if (!(s.real() > 0.0)) throw std::invalid_argument("potential_reference: A(s) needs Re s > 0");
    const auto inner = [&](double kx) {
      const cplx d = s + cplx(0.0, flow_.U() * kx);
      return Eigen::VectorXcd::Constant(1, 1.0 / std::sqrt(kx * kx + d * d / (flow_.a * flow_.a)));
    };
    const Eigen::VectorXcd I = outer_integral(s, inner, 1);
    const Eigen::Index nx = static_cast<Eigen::Index>(x_.size());
    return flow_.rho / (2.0 * std::numbers::pi) * I.reshaped(nx, nx).transpose();
  }

 private:
  /// (s + i U kx)^2: the factor of P that does not depend on ky.
  cplx pressure_factor(cplx s, double kx) const {
    const cplx d = s + cplx(0.0, flow_.U() * kx);
    return d * d;
  }

  static std::vector<detail::Mode1D> modes_1d(Edge edge, int count, double length) {
    std::vector<detail::Mode1D> v;
    for (int m = 1; m <= count; ++m) v.emplace_back(edge, m, length);
    return v;
  }
  /// Regular break points every pi / length up to cutoff / length (ky >= 0: the integrand is even in ky).
  std::vector<double> x_breaks(const std::vector<double>& extra) const {
    return detail::break_points(-acc_.cutoff / a_, acc_.cutoff / a_, std::numbers::pi / a_, extra);
  }
  std::vector<double> y_breaks(const std::vector<double>& extra) const {
    return detail::break_points(0.0, acc_.cutoff / b_, std::numbers::pi / b_, extra);
  }

  /// conj(X^_m) X^_m' at kx, as m nx + m'.
  Eigen::VectorXcd x_products(double kx) const {
    const Eigen::Index nx = static_cast<Eigen::Index>(x_.size());
    Eigen::VectorXcd t(nx), v(nx * nx);
    for (Eigen::Index m = 0; m < nx; ++m) t(m) = x_[m].transform(kx);
    for (Eigen::Index m = 0; m < nx; ++m) v.segment(m * nx, nx) = std::conj(t(m)) * t;
    return v;
  }
  /// 2 Re(conj(Y^_n) Y^_n') at ky (the sum of ky and -ky), as n ny + n'; zero for opposite parities.
  Eigen::VectorXcd y_products(double ky) const {
    const int ny = static_cast<int>(y_.size());
    Eigen::VectorXcd t(ny), v = Eigen::VectorXcd::Zero(ny * ny);
    for (int n = 0; n < ny; ++n) t(n) = y_[n].transform(ky);
    for (int n = 0; n < ny; ++n)
      for (int np = 0; np < ny; ++np)
        if (y_[n].parity() == y_[np].parity()) v(n * ny + np) = 2.0 * (std::conj(t(n)) * t(np)).real();
    return v;
  }

  /// ∫ conj(Y^_n) Y^_n' / mu dky over all ky for all (n, n'), as a vector n ny + n'.
  Eigen::VectorXcd y_integral(cplx s, double kx) const {
    const cplx d = s + cplx(0.0, flow_.U() * kx);
    const cplx c = kx * kx + d * d / (flow_.a * flow_.a);  // mu^2 = ky^2 + c
    const auto f = [&](double ky) -> Eigen::VectorXcd {
      const cplx inv_mu = 1.0 / std::sqrt(ky * ky + c);
      if (const Eigen::VectorXcd* kept = y_cache_.find(ky)) return *kept * inv_mu;
      return y_products(ky) * inv_mu;
    };
    const cplx root = std::sqrt(-c);  // mu nearly vanishes at ky = |Re root| when Im root is small
    return detail::integrate(f, y_breaks({std::abs(root.real())}), 0.1 * acc_.rel_tol);
  }

  /// ∫ (s + i U kx)^2 conj(X^_m) X^_m' inner(kx) dkx for all (m, m') and inner components q, as (m nx + m') nq + q.
  template <class Inner>
  Eigen::VectorXcd outer_integral(cplx s, const Inner& inner, int nq) const {
    const Eigen::Index nxx = static_cast<Eigen::Index>(x_.size() * x_.size());
    const auto f = [&](double kx) {
      const Eigen::VectorXcd* kept = x_cache_.find(kx);
      const Eigen::VectorXcd x = kept ? *kept : x_products(kx);
      const Eigen::VectorXcd in = inner(kx) * pressure_factor(s, kx);
      Eigen::VectorXcd v(nxx * nq);
      for (Eigen::Index j = 0; j < nxx; ++j) v.segment(j * nq, nq) = x(j) * in;
      return v;
    };
    // mu^2 = kx^2 + (s + i U kx)^2 / a^2 nearly vanishes where Im s + U kx = -+ a kx (sigma small).
    const double w = s.imag(), U = flow_.U(), a = flow_.a;
    return detail::integrate(f, x_breaks({0.0, -w / (U - a), -w / (U + a), -w / U}), acc_.rel_tol);
  }

  std::vector<int> modes_;
  Flow flow_;
  Accuracy acc_;
  double a_, b_;
  int my_;
  std::vector<detail::Mode1D> x_, y_;
  detail::NodeCache x_cache_, y_cache_;
};

/// Roots s of det(s^2 M + s B + C) = 0 (companion form; M symmetric positive definite).
inline Eigen::VectorXcd quadratic_roots(const Eigen::MatrixXd& M, const Eigen::MatrixXcd& B,
                                        const Eigen::MatrixXcd& C) {
  const Eigen::Index n = M.rows();
  const Eigen::LLT<Eigen::MatrixXd> llt(M);
  Eigen::MatrixXcd S = Eigen::MatrixXcd::Zero(2 * n, 2 * n);
  S.topRightCorner(n, n).setIdentity();
  S.bottomLeftCorner(n, n) = -llt.solve(C.real()).cast<cplx>() - cplx(0, 1) * llt.solve(C.imag()).cast<cplx>();
  S.bottomRightCorner(n, n) = -llt.solve(B.real()).cast<cplx>() - cplx(0, 1) * llt.solve(B.imag()).cast<cplx>();
  return Eigen::ComplexEigenSolver<Eigen::MatrixXcd>(S, false).eigenvalues();
}

/// A flutter root: s (1/s) and the p-k iterations it took.
struct Root {
  cplx s;
  int iterations = 0;
};

/// The root of det(s^2 M + K + A(s)) = 0 nearest s0, by successive linearisation of A about the current s.
inline Root flutter_root(const Eigen::MatrixXd& M, const Eigen::MatrixXd& K,
                         const std::function<Eigen::MatrixXcd(cplx)>& A, cplx s0, double tol = 1e-7,
                         int max_iterations = 30) {
  cplx s = s0, s_prev = s0 + 1e-4 * std::abs(s0);
  Eigen::MatrixXcd A_prev = A(s_prev);
  for (int it = 1; it <= max_iterations; ++it) {
    const Eigen::MatrixXcd A0 = A(s), A1 = (A0 - A_prev) / (s - s_prev);  // secant slope
    s_prev = s;
    A_prev = A0;
    const Eigen::VectorXcd r = quadratic_roots(M, A1, K.cast<cplx>() + A0 - s * A1);
    Eigen::Index k = 0;
    (r.array() - s).abs().minCoeff(&k);
    const cplx next = r(k);
    const bool done = std::abs(next - s) <= tol * std::abs(next);
    s = next;
    if (done) return {s, it};
  }
  throw std::runtime_error("potential_reference: the flutter root did not converge");
}

}  // namespace shellflow::testing::potential_reference
