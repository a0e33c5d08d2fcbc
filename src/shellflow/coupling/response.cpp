#include "shellflow/coupling/response.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "shellflow/core/json.h"

namespace shellflow::coupling {

namespace {

/// Least squares of log|w_k| = c + sigma t_k, with the standard error of sigma (n >= 2).
struct EnvelopeFit {
  double sigma = 0.0, c = 0.0, error = 0.0;
};
EnvelopeFit log_envelope_fit(std::span<const double> times, std::span<const double> values) {
  const std::size_t n = times.size();
  double st = 0, sy = 0, stt = 0, sty = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = times[i], y = std::log(std::abs(values[i]));
    st += x;
    sy += y;
    stt += x * x;
    sty += x * y;
  }
  const double dn = static_cast<double>(n);
  const double sxx = stt - st * st / dn;
  EnvelopeFit f;
  f.sigma = (sty - st * sy / dn) / sxx;
  f.c = (sy - f.sigma * st) / dn;
  double rss = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = std::log(std::abs(values[i])) - f.c - f.sigma * times[i];
    rss += r * r;
  }
  f.error = n > 2 ? std::sqrt(rss / (dn - 2.0) / sxx) : 0.0;
  return f;
}

/// Mean and sample standard deviation (NaN for one value).
std::pair<double, double> mean_and_spread(const std::vector<double>& x) {
  double mean = 0.0;
  for (const double v : x) mean += v / static_cast<double>(x.size());
  if (x.size() < 2) return {mean, std::nan("")};
  double ss = 0.0;
  for (const double v : x) ss += (v - mean) * (v - mean);
  return {mean, std::sqrt(ss / static_cast<double>(x.size() - 1))};
}

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

/// The frequency from the zero crossings between consecutive extrema (sample indices
/// `peaks`): least squares of c_k = c_0 + k T/2. A crossing is where w is steepest, so noise
/// moves it far less than it moves the time of a (flat) extremum; noise that makes several
/// crossings between two extrema gives their mean.
double crossing_frequency(std::span<const double> t, std::span<const double> w, const std::vector<std::size_t>& peaks) {
  std::vector<double> crossings;
  for (std::size_t k = 0; k + 1 < peaks.size(); ++k) {
    double sum = 0.0;
    int count = 0;
    for (std::size_t j = peaks[k]; j < peaks[k + 1]; ++j) {
      if (w[j] == 0.0) {
        sum += t[j];
        ++count;
      } else if (w[j] * w[j + 1] < 0.0) {
        sum += t[j] + (t[j + 1] - t[j]) * w[j] / (w[j] - w[j + 1]);
        ++count;
      }
    }
    if (count > 0) crossings.push_back(sum / count);
  }
  const std::size_t n = crossings.size();
  if (n < 2) return std::nan("");
  double sk = 0, skk = 0, st = 0, skt = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double k = static_cast<double>(i);
    sk += k;
    skk += k * k;
    st += crossings[i];
    skt += k * crossings[i];
  }
  const double dn = static_cast<double>(n);
  const double half_period = (skt - sk * st / dn) / (skk - sk * sk / dn);
  return 1.0 / (2.0 * half_period);
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
  const EnvelopeFit envelope = log_envelope_fit(fit.peak_times, fit.peak_values);
  fit.growth_rate = envelope.sigma;
  fit.growth_rate_error = envelope.error;
  const double dn = static_cast<double>(n);
  double st = 0;
  for (const double x : fit.peak_times) st += x;
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

ResponseAnalysis analyse_response(std::span<const double> t, std::span<const double> w,
                                  const ResponseOptions& options) {
  if (t.size() != w.size())
    throw std::invalid_argument(fmt::format("analyse_response: {} times but {} values", t.size(), w.size()));
  if (std::adjacent_find(t.begin(), t.end(), std::greater_equal<>()) != t.end())
    throw std::invalid_argument("analyse_response: the times must increase");
  if (options.lco_cycles < 1)
    throw std::invalid_argument(fmt::format("analyse_response: lco_cycles must be >= 1, got {}", options.lco_cycles));
  const double nan = std::nan("");
  ResponseAnalysis a;
  a.t_start = t.empty() ? nan : std::max(options.t_start, t.front());
  a.t_end = t.empty() ? nan : std::min(options.t_end, t.back());
  const ResponseFit fit = fit_response(t, w, options.t_start, options.t_end);
  a.extrema = fit.extrema;
  a.peak_times = fit.peak_times;
  a.peak_values = fit.peak_values;
  // fit_response's zeros mean "not measured" here: NaN, so that they cannot pass for a rate.
  a.frequency_hz =
      fit.extrema >= 3 ? crossing_frequency(t, w, half_cycle_peaks(t, w, options.t_start, options.t_end)) : nan;
  a.growth_rate = fit.extrema >= 3 ? fit.growth_rate : nan;
  a.growth_rate_error = fit.extrema >= 3 ? fit.growth_rate_error : nan;
  a.last_amplitude = a.peak_values.empty() ? nan : std::abs(a.peak_values.back());
  a.envelope_change = nan;

  // The last N cycles: their 2N + 1 extrema (both ends included).
  const auto cycles = static_cast<std::size_t>(options.lco_cycles);
  const std::size_t m = 2 * cycles + 1, n = a.peak_times.size();
  if (n < m) return a;
  const std::span<const double> times = std::span<const double>(a.peak_times).last(m);
  const std::span<const double> values = std::span<const double>(a.peak_values).last(m);
  double change = 0.0;
  for (const bool positive : {true, false}) {
    double lo = std::numeric_limits<double>::infinity(), hi = 0.0, sum = 0.0;
    int count = 0;
    for (const double v : values)
      if ((v > 0.0) == positive) {
        lo = std::min(lo, std::abs(v));
        hi = std::max(hi, std::abs(v));
        sum += std::abs(v);
        ++count;
      }
    if (count > 0) change = std::max(change, (hi - lo) / (sum / count));
  }
  a.envelope_change = change;
  a.saturated = a.envelope_change < options.saturation_threshold;
  if (!a.saturated) return a;
  LimitCycle lco;
  lco.cycles = options.lco_cycles;
  // Amplitude: each half-cycle once (the last 2N extrema: N of either sign).
  std::vector<double> amplitudes;
  for (std::size_t k = 1; k < m; ++k) amplitudes.push_back(std::abs(values[k]));
  std::tie(lco.amplitude, lco.amplitude_spread) = mean_and_spread(amplitudes);
  // Frequency: one value per full cycle, between extrema of the same sign.
  std::vector<double> frequencies;
  for (std::size_t k = 0; k < cycles; ++k) frequencies.push_back(1.0 / (times[2 * k + 2] - times[2 * k]));
  std::tie(lco.frequency_hz, lco.frequency_spread) = mean_and_spread(frequencies);
  a.lco = lco;
  return a;
}

namespace {

std::string json_array(const std::vector<double>& x) {
  std::string s = "[";
  for (std::size_t i = 0; i < x.size(); ++i) s += (i ? ", " : "") + json_number(x[i]);
  return s + "]";
}

}  // namespace

std::string response_to_json(const ResponseAnalysis& a, std::string_view probe) {
  std::string lco = "null";
  if (a.lco)
    lco = fmt::format(
        "{{\"amplitude\": {}, \"amplitude_spread\": {}, \"frequency_hz\": {}, "
        "\"frequency_spread\": {}, \"cycles\": {}}}",
        json_number(a.lco->amplitude), json_number(a.lco->amplitude_spread), json_number(a.lco->frequency_hz),
        json_number(a.lco->frequency_spread), a.lco->cycles);
  return fmt::format(
      "{{\"probe\": {}, \"window\": [{}, {}], \"frequency_hz\": {}, \"growth_rate\": {}, "
      "\"growth_rate_error\": {}, \"extrema\": {}, \"last_amplitude\": {}, \"envelope_change\": {}, "
      "\"saturated\": {}, \"lco\": {}, \"peak_times\": {}, \"peak_values\": {}}}",
      json_string(probe), json_number(a.t_start), json_number(a.t_end), json_number(a.frequency_hz),
      json_number(a.growth_rate), json_number(a.growth_rate_error), a.extrema, json_number(a.last_amplitude),
      json_number(a.envelope_change), a.saturated, lco, json_array(a.peak_times), json_array(a.peak_values));
}

}  // namespace shellflow::coupling
