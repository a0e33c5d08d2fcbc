// The bodies of von_karman_plate_reference.h (the model is documented there), compiled once for the tests.
#include "von_karman_plate_reference.h"

namespace shellflow::testing::von_karman {

std::pair<std::vector<double>, std::vector<double>> gauss_legendre(int n) {
  std::vector<double> x(n), w(n);
  for (int i = 0; i < n; ++i) {
    double z = std::cos(pi * (i + 0.75) / (n + 0.5)), dp = 1.0, dz = 1.0;
    for (int it = 0; it < 100 && std::abs(dz) > 1e-16; ++it) {  // Newton on P_n(z) = 0
      double p0 = 1.0, p1 = z;                                  // P_{k-1}, P_k by the three-term recurrence
      for (int k = 2; k <= n; ++k) p0 = std::exchange(p1, ((2 * k - 1) * z * p1 - (k - 1) * p0) / k);
      dp = n * (z * p1 - p0) / (z * z - 1.0), dz = p1 / dp, z -= dz;
    }
    x[i] = 0.5 * (1.0 - z);
    w[i] = 1.0 / ((1.0 - z * z) * dp * dp);  // 2/((1-z^2) P'^2) on [-1,1], halved for [0,1]
  }
  return {x, w};
}

BeamMode::BeamMode(int m) {
  beta = (m + 0.5) * pi;
  for (int it = 0; it < 100; ++it) {  // Newton on cos(b) - 1/cosh(b) = 0
    const double d = (std::cos(beta) - 1.0 / std::cosh(beta)) / (std::tanh(beta) / std::cosh(beta) - std::sin(beta));
    if (beta -= d; std::abs(d) < 1e-15 * beta) break;
  }
  const double e = std::exp(-beta), den = 1.0 - e * e - 2.0 * std::sin(beta) * e;
  sigma = (1.0 + e * e - 2.0 * std::cos(beta) * e) / den;
  r = (std::cos(beta) - std::sin(beta) - e) / den;
}

std::array<double, 3> BeamMode::operator()(double xi) const {
  const double b = beta, e0 = std::exp(-b * xi), e1 = std::exp(b * (xi - 1.0)), e2 = std::exp(-b * (xi + 1.0));
  const double c = std::cos(b * xi), s = std::sin(b * xi);
  return {e0 + r * (e1 - e2) - c + sigma * s, b * (-e0 + r * (e1 + e2) + s + sigma * c),
          b * b * (e0 + r * (e1 - e2) + c - sigma * s)};
}

Model::Model(const Params& s) : s_(s) {
  for (int m = 1; m <= s.modes_x; m += s.x_symmetric ? 2 : 1)
    for (int k = 1; k <= s.modes_y; ++k) index_.push_back({m, s.span_symmetric ? 2 * k - 1 : k});
  const int nw = size();
  int top_n = 1;
  for (auto [m, n] : index_) top_n = std::max(top_n, n);
  for (int m = 1; m <= std::max(s.modes_x, top_n); ++m) beams_.emplace_back(m);
  // Automatic rule: exact enough for products of four mode derivatives (checked against 60 points).
  const int nqx = s.quad > 0 ? s.quad : std::max(4 * s.modes_x + 12, s.inplane + 8);
  const int nqy = s.quad > 0 ? s.quad : std::max(4 * top_n + 12, s.inplane + 8);
  const auto [gx, wx] = gauss_legendre(nqx);
  const auto [gy, wy] = gauss_legendre(nqy);
  const int nq = nqx * nqy;  // point p = ix * nqy + iy; weights include the area a b
  wts_.resize(nq), phi_.resize(nq, nw), phix_.resize(nq, nw), phiy_.resize(nq, nw);
  Mat pxx(nq, nw), pyy(nq, nw), pxy(nq, nw);
  for (int ix = 0, p = 0; ix < nqx; ++ix)
    for (int iy = 0; iy < nqy; ++iy, ++p) {
      wts_(p) = wx[ix] * wy[iy] * s.a * s.b;
      for (int i = 0; i < nw; ++i) {
        const auto X = beams_[index_[i].first - 1](gx[ix]), Y = beams_[index_[i].second - 1](gy[iy]);
        phi_(p, i) = X[0] * Y[0], phix_(p, i) = X[1] * Y[0] / s.a, phiy_(p, i) = X[0] * Y[1] / s.b;
        pxx(p, i) = X[2] * Y[0] / (s.a * s.a), pyy(p, i) = X[0] * Y[2] / (s.b * s.b);
        pxy(p, i) = X[1] * Y[1] / (s.a * s.b);
      }
    }
  const auto W = wts_.asDiagonal();
  const double nu = s.nu;
  // Energy bilinear form B(a, b) = int [a_x (b_x + nu b_y) + a_y (b_y + nu b_x) + c a_g b_g] of two strain-like
  // triplets given at the points (bending: c = 2(1-nu) on the twist; membrane: c = (1-nu)/2 on the shear).
  auto form = [&](const Mat& ax, const Mat& ay, const Mat& ag, const Mat& bx, const Mat& by, const Mat& bg, double c) {
    return Mat(ax.transpose() * W * (bx + nu * by) + ay.transpose() * W * (by + nu * bx) + c * ag.transpose() * W * bg);
  };
  K_ = bending_stiffness(s) * form(pxx, pyy, pxy, pxx, pyy, pxy, 2.0 * (1.0 - nu));  // [N/m]
  shape_x_ = phi_.transpose() * W * phix_;                                           // [m]
  shape_m_ = phi_.transpose() * W * phi_;                                            // [m^2]
  load_ = phi_.transpose() * wts_;                                                   // [m^2]
  if (!s.nonlinear) return;
  // In-plane sine basis, u dofs then v dofs. A w symmetric about y = b/2 makes u symmetric (odd j) and v
  // antisymmetric (even j) there; likewise about x = a/2: u antisymmetric (even i), v symmetric (odd i).
  std::vector<std::array<int, 3>> uv;  // {component, i, j}
  for (int c = 0; c < 2; ++c)
    for (int i = 1; i <= s.inplane; ++i)
      for (int j = 1; j <= s.inplane; ++j)
        if ((!s.span_symmetric || (j % 2 == 1) == (c == 0)) && (!s.x_symmetric || (i % 2 == 0) == (c == 0)))
          uv.push_back({c, i, j});
  const int nuv = static_cast<int>(uv.size());
  lx_ = Mat::Zero(nq, nuv), ly_ = Mat::Zero(nq, nuv), lg_ = Mat::Zero(nq, nuv);  // eps_x, eps_y, gamma of (u, v)
  for (int ix = 0, p = 0; ix < nqx; ++ix)
    for (int iy = 0; iy < nqy; ++iy, ++p)
      for (int d = 0; d < nuv; ++d) {
        const auto [c, i, j] = uv[d];
        const double kx = i * pi / s.a, ky = j * pi / s.b, x = gx[ix] * s.a, y = gy[iy] * s.b;
        const double dx = kx * std::cos(kx * x) * std::sin(ky * y), dy = ky * std::sin(kx * x) * std::cos(ky * y);
        (c == 0 ? lx_(p, d) : ly_(p, d)) = c == 0 ? dx : dy;
        lg_(p, d) = c == 0 ? dy : dx;
      }
  am_ = s.E * s.h / (1.0 - nu * nu);
  kuv_.compute(am_ * form(lx_, ly_, lg_, lx_, ly_, lg_, 0.5 * (1.0 - nu)));
  // Quadratic strains per product s_p = q_j q_k (j <= k) such that (w_x^2/2, w_y^2/2, w_x w_y) = sum_p s_p e_p.
  for (int j = 0; j < nw; ++j)
    for (int k = j; k < nw; ++k) pairs_.push_back({j, k});
  const int np = static_cast<int>(pairs_.size());
  Mat ex(nq, np), ey(nq, np), eg(nq, np);
  for (int p = 0; p < np; ++p) {
    const auto [j, k] = pairs_[p];
    const double f = j == k ? 0.5 : 1.0;
    ex.col(p) = f * phix_.col(j).cwiseProduct(phix_.col(k));
    ey.col(p) = f * phiy_.col(j).cwiseProduct(phiy_.col(k));
    eg.col(p) = f * (phix_.col(j).cwiseProduct(phiy_.col(k)) + phiy_.col(j).cwiseProduct(phix_.col(k)));
  }
  // U_m = 1/2 c^T K_uv c + c^T H s + 1/2 s^T F s, minimised over c: c = -K_uv^-1 H s, G = F - H^T K_uv^-1 H [N/m^3].
  const Mat H = am_ * form(lx_, ly_, lg_, ex, ey, eg, 0.5 * (1.0 - nu));
  Mat G = am_ * form(ex, ey, eg, ex, ey, eg, 0.5 * (1.0 - nu));
  G.noalias() -= H.transpose() * kuv_.solve(H);
  G_ = 0.5 * (G + G.transpose());
}

Model::Vec Model::shape_at(double xi, double eta) const {
  Vec v(size());
  for (int i = 0; i < size(); ++i) v(i) = beams_[index_[i].first - 1](xi)[0] * beams_[index_[i].second - 1](eta)[0];
  return v;
}

Model::Vec Model::initial_q() const {
  Vec q = Vec::Zero(size());
  q(0) = s_.init_w / std::pow(beams_[0](0.5)[0], 2);
  return q;
}

double Model::membrane_energy(const Vec& q) const {
  const Vec sq = products(q);
  return 0.5 * sq.dot(G_ * sq);
}

Model::Vec Model::membrane_force(const Vec& q) const {
  Vec f = Vec::Zero(size());
  if (!s_.nonlinear) return f;
  const Vec g = G_ * products(q);
  for (std::size_t p = 0; p < pairs_.size(); ++p) {  // ds_p/dq_j = q_k, ds_p/dq_k = q_j
    f(pairs_[p].first) += g(p) * q(pairs_[p].second);
    f(pairs_[p].second) += g(p) * q(pairs_[p].first);
  }
  return f;
}

Model::Mat Model::membrane_jacobian(const Vec& q) const {
  Mat J = Mat::Zero(pairs_.size(), size()), S = Mat::Zero(size(), size());
  if (!s_.nonlinear) return S;
  const Vec g = G_ * products(q);
  for (std::size_t p = 0; p < pairs_.size(); ++p) {
    const auto [j, k] = pairs_[p];
    J(p, j) += q(k), J(p, k) += q(j), S(j, k) += g(p), S(k, j) += g(p);
  }
  return J.transpose() * G_ * J + S;
}

Model::Vec Model::membrane_force_direct(const Vec& q) const {
  const Vec wx = phix_ * q, wy = phiy_ * q;
  const Vec e0x = 0.5 * wx.cwiseProduct(wx), e0y = 0.5 * wy.cwiseProduct(wy), e0g = wx.cwiseProduct(wy);
  const double nu = s_.nu, c = 0.5 * (1.0 - nu);
  const auto W = wts_.asDiagonal();
  const Vec rhs = -am_ * (lx_.transpose() * W * (e0x + nu * e0y) + ly_.transpose() * W * (e0y + nu * e0x) +
                          c * lg_.transpose() * W * e0g);
  const Vec u = kuv_.solve(rhs);
  const Vec ex = lx_ * u + e0x, ey = ly_ * u + e0y, eg = lg_ * u + e0g;
  const Vec nx = am_ * (ex + nu * ey), ny = am_ * (ey + nu * ex), nxy = am_ * c * eg;
  return phix_.transpose() * W * (nx.cwiseProduct(wx) + nxy.cwiseProduct(wy)) +
         phiy_.transpose() * W * (ny.cwiseProduct(wy) + nxy.cwiseProduct(wx));
}

Model::Vec Model::products(const Vec& q) const {
  Vec sq(pairs_.size());
  for (std::size_t p = 0; p < pairs_.size(); ++p) sq(p) = q(pairs_[p].first) * q(pairs_[p].second);
  return sq;
}

Eigenvalue linear_eigenvalue(const Model& model, const Params& s) {
  const int n = model.size();
  const Eigen::MatrixXd minv = model.mass().inverse();
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  S.topRightCorner(n, n).setIdentity();
  S.bottomLeftCorner(n, n) = -minv * (model.stiffness() + dynamic_pressure(s) * model.shape_x());
  S.bottomRightCorner(n, n) = -minv * (damping_coefficient(s) * model.shape_m());
  const Eigen::VectorXcd ev = Eigen::EigenSolver<Eigen::MatrixXd>(S, false).eigenvalues();
  Eigen::Index k = 0;
  ev.real().maxCoeff(&k);
  return {ev(k).real(), std::abs(ev(k).imag()) / (2.0 * pi)};
}

Eigenvalue linear_eigenvalue(Params s) {
  s.nonlinear = false;
  return linear_eigenvalue(Model(s), s);
}

double flutter_mach(Params s, bool aero_damping) {
  s.nonlinear = false, s.aero_damping = aero_damping;
  const Model model(s);
  auto unstable = [&](double mach) {
    s.mach = mach;
    if (aero_damping) return linear_eigenvalue(model, s).growth_rate > 0.0;
    const Eigen::MatrixXd op = model.mass().inverse() * (model.stiffness() + dynamic_pressure(s) * model.shape_x());
    const Eigen::VectorXcd ev = Eigen::EigenSolver<Eigen::MatrixXd>(op, false).eigenvalues();
    return ev.imag().cwiseAbs().maxCoeff() > 1e-9 * ev.real().cwiseAbs().maxCoeff();
  };
  double lo = 1.5, hi = 1.75;
  for (; !unstable(hi); lo = hi, hi += 0.25)
    if (hi > 20.0) throw std::runtime_error("von_karman::flutter_mach: no flutter below M = 20");
  while (hi - lo > 1e-7) (unstable(0.5 * (lo + hi)) ? hi : lo) = 0.5 * (lo + hi);
  return 0.5 * (lo + hi);
}

History simulate(const Params& s, double t_end, double xi, double eta, int record_every) {
  const Model model(s);
  const Eigen::VectorXd probe = model.shape_at(xi, eta);
  History hist{{0.0}, {probe.dot(model.initial_q())}};
  long step = 0;
  integrate(model, t_end, [&](double t, const Eigen::VectorXd& q) {
    if (++step % record_every == 0) hist.t.push_back(t), hist.w.push_back(probe.dot(q));
    return true;
  });
  return hist;
}

bool CycleTracker::add(double t, double w) {
  bool done = false;
  if (n_ >= 2 && (w1_ - w0_) * (w1_ - w) > 0.0) {
    const double c = w - 2.0 * w1_ + w0_, ext = w1_ - (w - w0_) * (w - w0_) / (8.0 * c);
    hi_ = std::max(hi_, ext), lo_ = std::min(lo_, ext);
  }
  if (n_ >= 1 && w1_ < 0.0 && w >= 0.0) {
    const double tc = t1_ + (t - t1_) * w1_ / (w1_ - w);
    if ((done = started_)) starts.push_back(t0_), ends.push_back(tc), amplitudes.push_back(0.5 * (hi_ - lo_));
    started_ = true, t0_ = tc, hi_ = -1e300, lo_ = 1e300;
  }
  w0_ = w1_, w1_ = w, t1_ = t, ++n_;
  return done;
}

Response fit_growth(const History& h, double t_from) {
  CycleTracker c;
  for (std::size_t i = 0; i < h.t.size(); ++i) c.add(h.t[i], h.w[i]);
  double n = 0, st = 0, sy = 0, stt = 0, sty = 0, len = 0;
  for (std::size_t k = 0; k < c.amplitudes.size(); ++k) {
    if (c.starts[k] < t_from) continue;
    const double t = 0.5 * (c.starts[k] + c.ends[k]), y = std::log(c.amplitudes[k]);
    n += 1, st += t, sy += y, stt += t * t, sty += t * y, len += c.ends[k] - c.starts[k];
  }
  Response r;
  r.cycles = static_cast<int>(n);
  if (n >= 3) r.growth_rate = (n * sty - st * sy) / (n * stt - st * st), r.frequency_hz = n / len;
  return r;
}

Response lco_response(const Params& s, double t_max, double xi, double eta, double rel_change) {
  const Model model(s);
  const Eigen::VectorXd probe = model.shape_at(xi, eta);
  CycleTracker c;
  Response r;
  std::vector<Eigen::VectorXd> tail;
  double t_stop = t_max;
  integrate(model, t_max + 1.0, [&](double t, const Eigen::VectorXd& q) {
    if (r.converged) return tail.push_back(q), t < t_stop;
    if (c.add(t, probe.dot(q)) && c.amplitudes.size() >= 4) {
      const auto& A = c.amplitudes;
      const std::size_t k = A.size();
      r.converged = true;
      for (std::size_t j = k - 3; j < k; ++j) r.converged = r.converged && std::abs(A[j] / A[j - 1] - 1.0) < rel_change;
      if (r.converged) {
        r.time = t, r.lco_amplitude = (A[k - 1] + A[k - 2] + A[k - 3]) / 3.0;
        r.frequency_hz = 3.0 / (c.ends[k - 1] - c.ends[k - 4]), t_stop = t + 2.0 / r.frequency_hz;
      }
    }
    return r.converged || t < t_max;
  });
  r.cycles = static_cast<int>(c.amplitudes.size());
  if (!r.converged) {
    if (r.cycles > 0) r.lco_amplitude = c.amplitudes.back(), r.frequency_hz = 1.0 / (c.ends.back() - c.starts.back());
    return r;
  }
  const int gx = 41, gy = s.span_symmetric ? 21 : 41;
  Eigen::MatrixXd grid(gx * gy, model.size()), Q(model.size(), static_cast<Eigen::Index>(tail.size()));
  for (int i = 0; i < gx; ++i)
    for (int j = 0; j < gy; ++j) grid.row(i * gy + j) = model.shape_at(i / 40.0, j / 40.0).transpose();
  for (std::size_t k = 0; k < tail.size(); ++k) Q.col(static_cast<Eigen::Index>(k)) = tail[k];
  const Eigen::MatrixXd w = grid * Q;
  r.plate_max_amplitude = 0.5 * (w.rowwise().maxCoeff() - w.rowwise().minCoeff()).maxCoeff();
  return r;
}

Response lco_at_mach(double mach, Params s, double t_max) {
  s.mach = mach;
  return lco_response(s, t_max);
}

double static_center_deflection(const Params& s, double pressure, int steps) {
  const Model model(s);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model.size());
  for (int i = 1; i <= steps; ++i) {
    const Eigen::VectorXd f = pressure * i / steps * model.load();
    for (int it = 0; it < 50; ++it) {
      const Eigen::VectorXd res = model.stiffness() * q + model.membrane_force(q) - f;
      const Eigen::VectorXd dq = (model.stiffness() + model.membrane_jacobian(q)).ldlt().solve(res);
      q -= dq;
      if (dq.norm() <= 1e-12 * q.norm()) break;
    }
  }
  return model.shape_at(0.5, 0.5).dot(q);
}

}  // namespace shellflow::testing::von_karman
