#include "shellflow/coupling/acceleration.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "shellflow/core/error.h"

namespace shellflow::coupling {

std::string_view to_string(AccelerationType t) {
  switch (t) {
    case AccelerationType::none:
      return "none";
    case AccelerationType::constant:
      return "constant";
    case AccelerationType::aitken:
      return "aitken";
    case AccelerationType::iqn_ils:
      return "iqn_ils";
  }
  return "?";
}

double weighted_norm(std::span<const double> v, std::span<const double> weight) {
  double s = 0.0;
  for (std::size_t k = 0; k < v.size(); ++k) s += weight[k] * v[k] * v[k];
  return std::sqrt(s);
}

std::vector<double> block_scale(std::span<const double> v, std::span<const double> weight,
                                std::span<const std::size_t> blocks) {
  std::vector<double> scale(v.size(), 1.0);
  std::size_t from = 0;
  for (const std::size_t size : blocks) {
    if (from + size > v.size()) throw Error("coupling: the blocks of the interface vector overrun it");
    const double norm = weighted_norm(v.subspan(from, size), weight.subspan(from, size));
    if (norm > 0.0 && std::isfinite(norm)) std::fill_n(scale.begin() + std::ptrdiff_t(from), size, 1.0 / norm);
    from += size;
  }
  if (from != v.size()) throw Error("coupling: the blocks of the interface vector do not cover it");
  return scale;
}

namespace {

double weighted_dot(std::span<const double> a, std::span<const double> b, std::span<const double> weight) {
  double s = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) s += weight[k] * a[k] * b[k];
  return s;
}

class NoAcceleration final : public Acceleration {
 public:
  void update(std::span<double> x, std::span<const double> fx) override { std::copy(fx.begin(), fx.end(), x.begin()); }
};

class ConstantRelaxation final : public Acceleration {
 public:
  explicit ConstantRelaxation(double omega) : omega_(omega) {}
  void update(std::span<double> x, std::span<const double> fx) override {
    for (std::size_t k = 0; k < x.size(); ++k) x[k] += omega_ * (fx[k] - x[k]);
  }

 private:
  double omega_;
};

/// Aitken's dynamic relaxation. Each window starts from the last window's final factor,
/// capped by the initial relaxation in size (a large factor of a converged window is no
/// safe first step in the next one).
class Aitken final : public Acceleration {
 public:
  Aitken(double omega0, std::vector<double> weight, std::vector<std::size_t> blocks)
      : omega0_(omega0), omega_(omega0), area_(std::move(weight)), blocks_(std::move(blocks)) {
    weight_ = area_;
  }
  void begin_window() override {
    omega_ = std::copysign(std::min(omega0_, std::abs(omega_)), omega_);
    have_previous_ = false;
  }
  void update(std::span<double> x, std::span<const double> fx) override {
    const std::size_t n = x.size();
    if (!have_previous_ && blocks_.size() > 1) {
      // The window's block scaling: the area weights times 1/|H(x^0)_b|^2.
      const std::vector<double> scale = block_scale(fx, area_, blocks_);
      for (std::size_t k = 0; k < n; ++k) weight_[k] = area_[k] * scale[k] * scale[k];
    }
    residual_.resize(n);
    for (std::size_t k = 0; k < n; ++k) residual_[k] = fx[k] - x[k];
    if (have_previous_) {
      for (std::size_t k = 0; k < n; ++k) previous_[k] = residual_[k] - previous_[k];  // Δr
      const double dd = weighted_dot(previous_, previous_, weight_);
      // r^{k-1} . Δr = r^k . Δr - |Δr|^2
      if (dd > 0.0) omega_ = -omega_ * (weighted_dot(residual_, previous_, weight_) - dd) / dd;
    }
    for (std::size_t k = 0; k < n; ++k) x[k] += omega_ * residual_[k];
    previous_ = residual_;
    have_previous_ = true;
  }
  void save(ArchiveWriter& out) const override { out.put(omega_); }
  void restore(ArchiveReader& in) override {
    omega_ = in.get<double>();
    if (!std::isfinite(omega_)) throw Error(in.what() + ": the Aitken relaxation factor is not a finite number");
  }

 private:
  double omega0_, omega_;
  std::vector<double> area_, weight_, residual_, previous_;
  std::vector<std::size_t> blocks_;
  bool have_previous_ = false;
};

/// IQN-ILS. Columns are stored in the weighted scaling (sqrt(w) v) for V and unscaled for W;
/// with several blocks the least squares takes V and r times the window's block scaling.
class IqnIls final : public Acceleration {
 public:
  IqnIls(const AccelerationOptions& o, std::vector<double> weight, std::vector<std::size_t> blocks)
      : options_(o), weight_(std::move(weight)), blocks_(std::move(blocks)) {
    scale_.resize(Eigen::Index(weight_.size()));
    for (std::size_t k = 0; k < weight_.size(); ++k) scale_[Eigen::Index(k)] = std::sqrt(weight_[k]);
  }
  void begin_window() override {
    current_ = {};
    have_previous_ = false;
  }
  void end_window() override {
    if (options_.reuse > 0 && !current_.v.empty()) {
      past_.push_front(std::move(current_));
      while (past_.size() > std::size_t(options_.reuse)) past_.pop_back();
    }
    current_ = {};
    have_previous_ = false;
  }
  void update(std::span<double> x, std::span<const double> fx) override {
    const Eigen::Index n = Eigen::Index(x.size());
    const Eigen::Map<const Eigen::VectorXd> fxv(fx.data(), n);
    Eigen::Map<Eigen::VectorXd> xv(x.data(), n);
    const Eigen::VectorXd r = scale_.cwiseProduct(fxv - xv);  // scaled residual
    if (!have_previous_ && blocks_.size() > 1) {
      const std::vector<double> scale = block_scale(fx, weight_, blocks_);
      block_ = Eigen::Map<const Eigen::VectorXd>(scale.data(), n);
    }
    if (have_previous_) {
      current_.v.insert(current_.v.begin(), r - previous_r_);
      current_.w.insert(current_.w.begin(), fxv - previous_fx_);
    }
    previous_r_ = r;
    previous_fx_ = fxv;
    have_previous_ = true;
    // Columns newest first: this window's, then the reused windows'.
    std::vector<const Eigen::VectorXd*> vs, ws;
    const auto gather = [&](const Window& win) {
      for (std::size_t j = 0; j < win.v.size() && vs.size() < std::size_t(options_.columns); ++j) {
        vs.push_back(&win.v[j]);
        ws.push_back(&win.w[j]);
      }
    };
    gather(current_);
    for (const Window& win : past_) gather(win);
    if (vs.empty()) {
      xv += options_.relaxation * (fxv - xv);
      return;
    }
    // Modified Gram–Schmidt, newest column first; a column whose orthogonal part is below
    // filter x its norm depends on the newer ones and is dropped (QR1 filter).
    std::vector<Eigen::VectorXd> q;
    std::vector<std::size_t> kept;
    Eigen::MatrixXd R = Eigen::MatrixXd::Zero(Eigen::Index(vs.size()), Eigen::Index(vs.size()));
    const bool blocked = blocks_.size() > 1;
    for (std::size_t j = 0; j < vs.size(); ++j) {
      Eigen::VectorXd a = blocked ? Eigen::VectorXd(block_.cwiseProduct(*vs[j])) : *vs[j];
      const double norm = a.norm();
      Eigen::VectorXd coeff(Eigen::Index(q.size()));
      for (std::size_t i = 0; i < q.size(); ++i) {
        coeff[Eigen::Index(i)] = q[i].dot(a);
        a -= coeff[Eigen::Index(i)] * q[i];
      }
      const double rest = a.norm();
      if (!(norm > 0.0) || rest <= options_.filter * norm) continue;
      const Eigen::Index c = Eigen::Index(q.size());
      R.col(c).head(c) = coeff;
      R(c, c) = rest;
      q.push_back(a / rest);
      kept.push_back(j);
    }
    if (q.empty()) {
      xv += options_.relaxation * (fxv - xv);
      return;
    }
    const Eigen::Index m = Eigen::Index(q.size());
    Eigen::VectorXd rhs(m);
    const Eigen::VectorXd rb = blocked ? Eigen::VectorXd(block_.cwiseProduct(r)) : r;
    for (Eigen::Index i = 0; i < m; ++i) rhs[i] = -q[std::size_t(i)].dot(rb);
    const Eigen::VectorXd c = R.topLeftCorner(m, m).triangularView<Eigen::Upper>().solve(rhs);
    xv = fxv;
    for (Eigen::Index i = 0; i < m; ++i) xv += c[i] * *ws[kept[std::size_t(i)]];
  }
  void save(ArchiveWriter& out) const override {
    out.put(std::uint64_t(past_.size()));
    for (const Window& win : past_) {
      out.put(std::uint64_t(win.v.size()));
      for (std::size_t j = 0; j < win.v.size(); ++j) {
        out.put(win.v[j]);
        out.put(win.w[j]);
      }
    }
  }
  void restore(ArchiveReader& in) override {
    past_.clear();
    const auto windows = in.get<std::uint64_t>();
    if (windows > std::uint64_t(options_.reuse))
      throw Error(in.what() + ": the IQN-ILS history holds more windows than coupling.acceleration.reuse");
    for (std::uint64_t i = 0; i < windows; ++i) {
      Window win;
      const auto columns = in.get<std::uint64_t>();
      if (columns > in.remaining()) throw Error(in.what() + ": the IQN-ILS history is damaged");
      for (std::uint64_t j = 0; j < columns; ++j) {
        win.v.push_back(in.get_eigen());
        win.w.push_back(in.get_eigen());
        in.expect_size("an IQN-ILS column", std::size_t(win.v.back().size()), std::size_t(scale_.size()));
        in.expect_size("an IQN-ILS column", std::size_t(win.w.back().size()), std::size_t(scale_.size()));
      }
      past_.push_back(std::move(win));
    }
  }

 private:
  struct Window {
    std::vector<Eigen::VectorXd> v, w;  ///< newest first
  };
  AccelerationOptions options_;
  std::vector<double> weight_;
  std::vector<std::size_t> blocks_;
  Eigen::VectorXd scale_, block_, previous_r_, previous_fx_;
  bool have_previous_ = false;
  Window current_;
  std::deque<Window> past_;  ///< newest first
};

}  // namespace

std::unique_ptr<Acceleration> make_acceleration(const AccelerationOptions& o, std::vector<double> weight,
                                                std::vector<std::size_t> blocks) {
  switch (o.type) {
    case AccelerationType::none:
      return std::make_unique<NoAcceleration>();
    case AccelerationType::constant:
      return std::make_unique<ConstantRelaxation>(o.relaxation);
    case AccelerationType::aitken:
      return std::make_unique<Aitken>(o.relaxation, std::move(weight), std::move(blocks));
    case AccelerationType::iqn_ils:
      return std::make_unique<IqnIls>(o, std::move(weight), std::move(blocks));
  }
  throw Error("coupling: unknown acceleration");
}

}  // namespace shellflow::coupling
