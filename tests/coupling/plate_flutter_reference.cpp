// The bodies of plate_flutter_reference.h (the model is documented there), compiled once for the tests.
#include "plate_flutter_reference.h"

namespace shellflow::testing::plate_reference {

namespace detail {

void gauss_legendre(int n, Eigen::VectorXd& x, Eigen::VectorXd& w) {
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

double clamped_beta(int m) {
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

BeamCoefficients clamped_beam_coefficients(double beta) {
  const double eb = std::exp(-beta), s = std::sin(beta), c = std::cos(beta);
  const double den = 1.0 - eb * eb - 2.0 * s * eb;
  return {(1.0 + eb * eb - 2.0 * c * eb) / den, (c - s - eb) / den};
}

double clamped_beam(double beta, double xi, int p) {
  const auto [sigma, c1] = clamped_beam_coefficients(beta);
  const double e1 = 0.5 * (1.0 + sigma) * std::exp(-beta * xi), e2 = c1 * std::exp(-beta * (1.0 - xi));
  const double cx = std::cos(beta * xi), sx = std::sin(beta * xi);
  if (p == 0) return e1 + e2 - cx + sigma * sx;
  if (p == 1) return beta * (-e1 + e2 + sx + sigma * cx);
  return beta * beta * (e1 + e2 + cx - sigma * sx);
}

Basis1D::Basis1D(Edge edge, int n, double L, const Eigen::VectorXd& xi) {
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

Eigen::MatrixXd integral(const Basis1D& F, int p, const Basis1D& G, int q, const Eigen::VectorXd& wq, double L) {
  return F.f[p].transpose() * (L * wq).asDiagonal() * G.f[q];
}

Eigen::MatrixXd kron(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y) {
  Eigen::MatrixXd Z(X.rows() * Y.rows(), X.cols() * Y.cols());
  for (Eigen::Index i = 0; i < X.rows(); ++i)
    for (Eigen::Index j = 0; j < X.cols(); ++j) Z.block(i * Y.rows(), j * Y.cols(), Y.rows(), Y.cols()) = X(i, j) * Y;
  return Z;
}

}  // namespace detail

Matrices assemble(const Plate& p) {
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

std::vector<double> natural_frequencies_hz(const Matrices& m) {
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(m.K, m.M, Eigen::EigenvaluesOnly);
  std::vector<double> f;
  for (Eigen::Index i = 0; i < es.eigenvalues().size(); ++i)
    f.push_back(std::sqrt(std::max(0.0, es.eigenvalues()(i))) / (2.0 * std::numbers::pi));
  return f;
}

FlutterProblem::FlutterProblem(const Plate& p, const Matrices& m, double g_D) {
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

FlutterProblem::Root FlutterProblem::least_stable(double lambda) const {
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

Flutter critical_lambda(const Plate& p, const Matrices& m, double g_D, const ScanOptions& o) {
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

}  // namespace shellflow::testing::plate_reference
