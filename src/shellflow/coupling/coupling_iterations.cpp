#include "shellflow/coupling/coupling_iterations.h"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "shellflow/core/error.h"

namespace shellflow::coupling {

CouplingIterations::CouplingIterations(CouplingIterationOptions options, std::vector<double> weight,
                                       std::vector<std::size_t> blocks)
    : options_(options),
      weight_(std::move(weight)),
      blocks_(blocks.empty() ? std::vector<std::size_t>{weight_.size()} : blocks),
      acceleration_(make_acceleration(options.acceleration, weight_, std::move(blocks))) {
  std::size_t total = 0;
  for (const std::size_t size : blocks_) total += size;
  if (total != weight_.size())
    throw Error(fmt::format("coupling: blocks of {} entries for an interface vector of {}", total, weight_.size()));
  x_.assign(weight_.size(), 0.0);
  difference_.assign(weight_.size(), 0.0);
  noise_norm_ = weighted_norm(std::vector<double>(weight_.size(), options_.noise_pressure), weight_);
}

void CouplingIterations::begin(std::span<const double> guess) {
  x_.assign(guess.begin(), guess.end());
  iteration_ = 0;
  residual_ = 0.0;
  acceleration_->begin_window();
}

namespace {
/// |r| / |f| (0 when both vanish).
double relative(double r, double f) {
  return r == 0.0 ? 0.0 : f > 0.0 ? r / f : std::numeric_limits<double>::infinity();
}
}  // namespace

CouplingIterations::Outcome CouplingIterations::result(std::span<const double> result) {
  ++iteration_;
  for (std::size_t k = 0; k < x_.size(); ++k) difference_[k] = result[k] - x_[k];
  const double r = weighted_norm(difference_, weight_), f = weighted_norm(result, weight_);
  residual_ = relative(r, f);
  if (!std::isfinite(f)) return Outcome::diverged;
  if (!implicit()) return explicit_step(f);  // its blow-up monitor reads the whole vector's residual
  if (blocks_.size() > 1) {
    const std::span<const double> d(difference_), w(weight_);
    residual_ = 0.0;
    std::size_t from = 0;
    for (const std::size_t size : blocks_) {
      residual_ = std::max(residual_, relative(weighted_norm(d.subspan(from, size), w.subspan(from, size)),
                                               weighted_norm(result.subspan(from, size), w.subspan(from, size))));
      from += size;
    }
  }
  if (residual_ <= options_.tolerance) {
    acceleration_->end_window();
    return Outcome::done;
  }
  if (iteration_ >= options_.max_iterations) return Outcome::not_converged;
  acceleration_->update(x_, result);
  return Outcome::again;
}

CouplingIterations::Outcome CouplingIterations::explicit_step(double load_norm) {
  // The explicit scheme's instability shows as a load that jumps from step to step and
  // grows: the prediction misses the flow's loads by a good part of their size, step after
  // step. (A load of round-off size at rest misses as much, but it does not grow.)
  if (steps_ >= std::int64_t(recent_.size())) earlier_peak_ = std::max(earlier_peak_, recent_.front().load_norm);
  std::rotate(recent_.begin(), recent_.begin() + 1, recent_.end());
  recent_.back() = {residual_, load_norm};
  if (++steps_ < 2 * std::int64_t(recent_.size())) return Outcome::done;
  const auto missed =
      std::count_if(recent_.begin(), recent_.end(), [](const Recent& r) { return r.residual > kBlowUpMiss; });
  const bool grew = load_norm > kBlowUpGrowth * earlier_peak_ && load_norm > noise_norm_;
  return missed >= kBlowUpMissed && grew ? Outcome::diverged : Outcome::done;
}

void CouplingIterations::save(ArchiveWriter& out) const {
  acceleration_->save(out);
  out.put(steps_);
  out.put(earlier_peak_);
  for (const Recent& r : recent_) {
    out.put(r.residual);
    out.put(r.load_norm);
  }
}

void CouplingIterations::restore(ArchiveReader& in) {
  acceleration_->restore(in);
  steps_ = in.get<std::int64_t>();
  earlier_peak_ = in.get<double>();
  for (Recent& r : recent_) {
    r.residual = in.get<double>();
    r.load_norm = in.get<double>();
  }
}

double staggered_spectral_radius(double ratio, double omega_dt, LoadPredictor predictor) {
  // State (x, v, a, F_n, F_n-1) in units m = dt = 1: k = omega_dt^2, rho c = ratio. The step
  // applies f = F_n (or 2 F_n - F_n-1) at its end, Newmark beta 1/4, gamma 1/2, then
  // F_n+1 = -rho c v_n+1.
  const double k = omega_dt * omega_dt;
  Eigen::Matrix<double, 5, 5> A;
  for (int j = 0; j < 5; ++j) {
    Eigen::Matrix<double, 5, 1> s = Eigen::Matrix<double, 5, 1>::Zero();
    s[j] = 1.0;
    const double x = s[0], v = s[1], a = s[2], fn = s[3], fm = s[4];
    const double f = predictor == LoadPredictor::linear ? 2.0 * fn - fm : fn;
    const double a1 = (f - k * (x + v + 0.25 * a)) / (1.0 + 0.25 * k);
    const double x1 = x + v + 0.25 * (a + a1), v1 = v + 0.5 * (a + a1);
    A.col(j) << x1, v1, a1, -ratio * v1, fn;
  }
  return A.eigenvalues().cwiseAbs().maxCoeff();
}

double staggered_critical_ratio(LoadPredictor predictor, double omega_dt) {
  constexpr double slack = 1e-12;
  double lo = 0.0, hi = 10.0;
  if (staggered_spectral_radius(1e-6, omega_dt, predictor) > 1.0 + slack) return 0.0;
  for (int i = 0; i < 80; ++i) {
    const double mid = 0.5 * (lo + hi);
    (staggered_spectral_radius(mid, omega_dt, predictor) > 1.0 + slack ? hi : lo) = mid;
  }
  return lo;
}

}  // namespace shellflow::coupling
