// The bodies of potential_flow_reference.h (the model is documented there), compiled once for the tests.
#include "potential_flow_reference.h"

namespace shellflow::testing::potential_reference {

namespace detail {

cplx expm1_over(cplx w) {
  if (std::abs(w) < 1e-2) return 1.0 + w * (1.0 / 2 + w * (1.0 / 6 + w * (1.0 / 24 + w * (1.0 / 120 + w / 720.0))));
  return (std::exp(w) - 1.0) / w;
}

Mode1D::Mode1D(Edge edge, int index, double length) : L_(length), parity_(index % 2 == 1 ? 1 : -1) {
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

cplx Mode1D::transform(double k) const {
  const double kappa = k * L_;
  cplx sum = 0.0;
  for (const Term& t : terms_) {
    const cplx w = t.z - cplx(0.0, kappa);
    sum += t.xi0 == 0 ? t.c * expm1_over(w) : t.c * std::exp(cplx(0.0, -kappa)) * expm1_over(-w);
  }
  return L_ * sum;
}

std::array<double, 15> kronrod_nodes(double lo, double hi) {
  const double c = 0.5 * (lo + hi), h = 0.5 * (hi - lo);
  std::array<double, 15> x{};
  x[0] = c;
  for (int j = 0; j < 7; ++j) {
    x[1 + 2 * j] = c - h * kronrod_x[j];
    x[2 + 2 * j] = c + h * kronrod_x[j];
  }
  return x;
}

template <class F>
Eigen::VectorXcd integrate(const F& f, std::vector<double> breaks, double rel_tol, int max_pieces) {
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

std::vector<double> break_points(double lo, double hi, double spacing, const std::vector<double>& extra) {
  std::vector<double> b;
  const int n = static_cast<int>(std::ceil((hi - lo) / spacing));
  for (int j = 0; j <= n; ++j) b.push_back(lo + (hi - lo) * j / n);
  for (const double e : extra)
    if (e > lo && e < hi) b.push_back(e);
  return b;
}

template <class G>
NodeCache::NodeCache(const std::vector<double>& breaks, const G& g) {
  for (std::size_t j = 0; j + 1 < breaks.size(); ++j)
    for (const double x : kronrod_nodes(breaks[j], breaks[j + 1])) entries_.push_back({x, g(x)});
  std::sort(entries_.begin(), entries_.end(), [](const auto& l, const auto& r) { return l.k < r.k; });
}

const Eigen::VectorXcd* NodeCache::find(double k) const {
  const auto it =
      std::lower_bound(entries_.begin(), entries_.end(), k, [](const auto& e, double x) { return e.k < x; });
  return it != entries_.end() && it->k == k ? &it->value : nullptr;
}

}  // namespace detail

Aerodynamics::Aerodynamics(const Plate& p, std::vector<int> modes, const Flow& flow, Accuracy acc)
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

Eigen::MatrixXcd Aerodynamics::matrix(cplx s) const {
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

Eigen::MatrixXcd Aerodynamics::matrix_2d(cplx s) const {
  if (!(s.real() > 0.0)) throw std::invalid_argument("potential_reference: A(s) needs Re s > 0");
  const auto inner = [&](double kx) {
    const cplx d = s + cplx(0.0, flow_.U() * kx);
    return Eigen::VectorXcd::Constant(1, 1.0 / std::sqrt(kx * kx + d * d / (flow_.a * flow_.a)));
  };
  const Eigen::VectorXcd I = outer_integral(s, inner, 1);
  const Eigen::Index nx = static_cast<Eigen::Index>(x_.size());
  return flow_.rho / (2.0 * std::numbers::pi) * I.reshaped(nx, nx).transpose();
}

cplx Aerodynamics::pressure_factor(cplx s, double kx) const {
  const cplx d = s + cplx(0.0, flow_.U() * kx);
  return d * d;
}

std::vector<detail::Mode1D> Aerodynamics::modes_1d(Edge edge, int count, double length) {
  std::vector<detail::Mode1D> v;
  for (int m = 1; m <= count; ++m) v.emplace_back(edge, m, length);
  return v;
}

std::vector<double> Aerodynamics::x_breaks(const std::vector<double>& extra) const {
  return detail::break_points(-acc_.cutoff / a_, acc_.cutoff / a_, std::numbers::pi / a_, extra);
}

std::vector<double> Aerodynamics::y_breaks(const std::vector<double>& extra) const {
  return detail::break_points(0.0, acc_.cutoff / b_, std::numbers::pi / b_, extra);
}

Eigen::VectorXcd Aerodynamics::x_products(double kx) const {
  const Eigen::Index nx = static_cast<Eigen::Index>(x_.size());
  Eigen::VectorXcd t(nx), v(nx * nx);
  for (Eigen::Index m = 0; m < nx; ++m) t(m) = x_[m].transform(kx);
  for (Eigen::Index m = 0; m < nx; ++m) v.segment(m * nx, nx) = std::conj(t(m)) * t;
  return v;
}

Eigen::VectorXcd Aerodynamics::y_products(double ky) const {
  const int ny = static_cast<int>(y_.size());
  Eigen::VectorXcd t(ny), v = Eigen::VectorXcd::Zero(ny * ny);
  for (int n = 0; n < ny; ++n) t(n) = y_[n].transform(ky);
  for (int n = 0; n < ny; ++n)
    for (int np = 0; np < ny; ++np)
      if (y_[n].parity() == y_[np].parity()) v(n * ny + np) = 2.0 * (std::conj(t(n)) * t(np)).real();
  return v;
}

Eigen::VectorXcd Aerodynamics::y_integral(cplx s, double kx) const {
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

template <class Inner>
Eigen::VectorXcd Aerodynamics::outer_integral(cplx s, const Inner& inner, int nq) const {
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

Eigen::VectorXcd quadratic_roots(const Eigen::MatrixXd& M, const Eigen::MatrixXcd& B, const Eigen::MatrixXcd& C) {
  const Eigen::Index n = M.rows();
  const Eigen::LLT<Eigen::MatrixXd> llt(M);
  Eigen::MatrixXcd S = Eigen::MatrixXcd::Zero(2 * n, 2 * n);
  S.topRightCorner(n, n).setIdentity();
  S.bottomLeftCorner(n, n) = -llt.solve(C.real()).cast<cplx>() - cplx(0, 1) * llt.solve(C.imag()).cast<cplx>();
  S.bottomRightCorner(n, n) = -llt.solve(B.real()).cast<cplx>() - cplx(0, 1) * llt.solve(B.imag()).cast<cplx>();
  return Eigen::ComplexEigenSolver<Eigen::MatrixXcd>(S, false).eigenvalues();
}

Root flutter_root(const Eigen::MatrixXd& M, const Eigen::MatrixXd& K, const std::function<Eigen::MatrixXcd(cplx)>& A,
                  cplx s0, double tol, int max_iterations) {
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
