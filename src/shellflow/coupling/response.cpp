#include "shellflow/coupling/response.h"

#include <cmath>

namespace shellflow::coupling {

namespace {

/// The extremum of each half-cycle: the largest |w| between sign changes of w, after merging
/// away half-cycles whose peak is below `floor` times that of a neighbour (noise around the
/// zero crossings makes spurious short ones).
std::vector<std::size_t> half_cycle_peaks(std::span<const double> t, std::span<const double> w, double t_start,
                                          double t_end, double floor = 0.2) {
  struct Segment {
    std::size_t peak;
    bool positive;
  };
  std::vector<Segment> seg;
  for (std::size_t i = 0; i < w.size(); ++i) {
    if (t[i] < t_start || t[i] > t_end || w[i] == 0.0) continue;
    const bool positive = w[i] > 0.0;
    if (seg.empty() || seg.back().positive != positive) {
      seg.push_back({i, positive});
    } else if (std::abs(w[i]) > std::abs(w[seg.back().peak])) {
      seg.back().peak = i;
    }
  }
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t k = 0; k < seg.size(); ++k) {
      const double a = std::abs(w[seg[k].peak]);
      const double prev = k > 0 ? std::abs(w[seg[k - 1].peak]) : 0.0;
      const double next = k + 1 < seg.size() ? std::abs(w[seg[k + 1].peak]) : 0.0;
      if (a >= floor * std::max(prev, next)) continue;
      // Drop it and merge its neighbours (then of the same sign).
      seg.erase(seg.begin() + std::ptrdiff_t(k));
      if (k > 0 && k < seg.size() && seg[k - 1].positive == seg[k].positive) {
        if (std::abs(w[seg[k].peak]) > std::abs(w[seg[k - 1].peak])) seg[k - 1].peak = seg[k].peak;
        seg.erase(seg.begin() + std::ptrdiff_t(k));
      }
      changed = true;
      break;
    }
  }
  // The first and last half-cycles may be cut by the window: drop them.
  std::vector<std::size_t> peaks;
  for (std::size_t k = 1; k + 1 < seg.size(); ++k) peaks.push_back(seg[k].peak);
  return peaks;
}

}  // namespace

ResponseFit fit_response(std::span<const double> t, std::span<const double> w, double t_start, double t_end) {
  ResponseFit fit;
  for (const std::size_t i : half_cycle_peaks(t, w, t_start, t_end)) {
    if (i == 0 || i + 1 >= w.size()) continue;
    // Parabola through (t[i-1], t[i], t[i+1]) (uniform or not).
    const double h0 = t[i] - t[i - 1], h1 = t[i + 1] - t[i];
    const double d0 = (w[i] - w[i - 1]) / h0, d1 = (w[i + 1] - w[i]) / h1;
    const double a = (d1 - d0) / (h0 + h1);  // w'' / 2
    const double b = d0 + a * h0;            // w'(t_i) of the parabola
    double tp = t[i], wp = w[i];
    if (a != 0.0) {
      const double s = -b / (2.0 * a);
      if (std::abs(s) <= std::max(h0, h1)) {
        tp = t[i] + s;
        wp = w[i] + b * s + a * s * s;
      }
    }
    fit.peak_times.push_back(tp);
    fit.peak_values.push_back(wp);
  }
  const std::size_t n = fit.peak_times.size();
  fit.extrema = static_cast<int>(n);
  if (n < 3) return fit;
  fit.last_amplitude = std::abs(fit.peak_values.back());
  // Growth: least squares of log|w| = c + sigma t.
  double st = 0, sy = 0, stt = 0, sty = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = fit.peak_times[i], y = std::log(std::abs(fit.peak_values[i]));
    st += x;
    sy += y;
    stt += x * x;
    sty += x * y;
  }
  const double dn = static_cast<double>(n);
  const double sxx = stt - st * st / dn;
  fit.growth_rate = (sty - st * sy / dn) / sxx;
  const double c = (sy - fit.growth_rate * st) / dn;
  double rss = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = std::log(std::abs(fit.peak_values[i])) - c - fit.growth_rate * fit.peak_times[i];
    rss += r * r;
  }
  fit.growth_rate_error = n > 2 ? std::sqrt(rss / (dn - 2.0) / sxx) : 0.0;
  // Frequency: extrema are half a period apart; least squares of t_k = t_0 + k T/2.
  double sk = 0, skk = 0, skt = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double k = static_cast<double>(i);
    sk += k;
    skk += k * k;
    skt += k * fit.peak_times[i];
  }
  const double half_period = (skt - sk * st / dn) / (skk - sk * sk / dn);
  fit.frequency_hz = 1.0 / (2.0 * half_period);
  return fit;
}

}  // namespace shellflow::coupling
