#pragma once
// Response analysis of a probe history w(t) (a flutter run): one extremum per half-cycle
// (the largest |w| between sign changes, noise-made short half-cycles merged away),
// the growth rate sigma of their envelope |w_peak| ~ exp(sigma t) (least-squares fit of
// log|w_peak| against the peak times, with its standard error), and the frequency from the
// spacing of the extrema (half periods). Peak times and values are refined by a parabola
// through the sample and its neighbours.
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace shellflow::coupling {

struct ResponseFit {
  double frequency_hz = 0.0;
  double growth_rate = 0.0;        ///< sigma [1/s]
  double growth_rate_error = 0.0;  ///< standard error of sigma [1/s]
  int extrema = 0;                 ///< extrema in the window
  double last_amplitude = 0.0;     ///< |w| of the last extremum
  std::vector<double> peak_times, peak_values;
};

/// Fits the extrema of w within [t_start, t_end]. Needs at least 3 extrema (else the fit is
/// returned with extrema < 3 and zero rates).
ResponseFit fit_response(std::span<const double> t, std::span<const double> w, double t_start, double t_end);

/// What analyse_response() looks at.
struct ResponseOptions {
  /// The window [t_start, t_end] of the growth fit and of the extrema (default: all of w).
  double t_start = -std::numeric_limits<double>::infinity();
  double t_end = std::numeric_limits<double>::infinity();
  int lco_cycles = 5;  ///< N: the last N full cycles of the window make the limit cycle (>= 1)
  /// Saturation rule: over the last N cycles of the window (their 2N + 1 extrema), the
  /// envelope change is (max |w| - min |w|) / mean |w|, taken over the positive and over the
  /// negative extrema separately and the larger of the two; the response is saturated when it
  /// is below this threshold (amplitude constant to about 5 % across those cycles). Taking the
  /// signs apart lets an asymmetric limit cycle (unequal positive and negative peaks) count
  /// as saturated; a range rather than the slope of a fit over those cycles catches a beat
  /// whose maximum falls among them (flat on average, not constant). A growing envelope
  /// exp(sigma t) gives about |sigma| times the duration of the N cycles (when that is small).
  double saturation_threshold = 0.05;
};

/// A saturated response: the last N cycles of the window.
struct LimitCycle {
  double amplitude = 0.0;         ///< mean |w| of their 2N half-cycle extrema
  double amplitude_spread = 0.0;  ///< standard deviation of those |w| (N = 1: of 2 values)
  double frequency_hz = 0.0;      ///< mean of 1/T_k over the N full cycles (T_k = t_{2k+2} - t_{2k})
  double frequency_spread = 0.0;  ///< standard deviation of those 1/T_k; NaN for N = 1
  int cycles = 0;                 ///< N
};

/// The response of one probe history (docs/coupling.md "Response analysis").
struct ResponseAnalysis {
  double t_start = 0.0, t_end = 0.0;  ///< the window, clipped to the samples
  /// Over the window; NaN with fewer than 3 extrema. The growth rate is fit_response's; the
  /// frequency comes from the zero crossings between the extrema (least squares of their
  /// times, half a period apart), which noise moves far less than the extrema's times.
  double frequency_hz = 0.0;
  double growth_rate = 0.0;        ///< sigma [1/s]
  double growth_rate_error = 0.0;  ///< standard error of sigma [1/s]
  int extrema = 0;
  double last_amplitude = 0.0;  ///< |w| of the last extremum (NaN without extrema)
  /// The envelope change of the last N cycles (ResponseOptions::saturation_threshold); NaN
  /// with fewer than 2N + 1 extrema in the window.
  double envelope_change = 0.0;
  bool saturated = false;
  std::optional<LimitCycle> lco;  ///< when saturated
  std::vector<double> peak_times, peak_values;
};

/// Growth, frequency and (when saturated) the limit cycle of w(t). t increasing, same size as
/// w; throws std::invalid_argument otherwise or for lco_cycles < 1.
ResponseAnalysis analyse_response(std::span<const double> t, std::span<const double> w,
                                  const ResponseOptions& options = {});

/// The analysis as one JSON object (`probe` names the history): "probe", "window": [t0, t1],
/// "frequency_hz", "growth_rate", "growth_rate_error", "extrema", "last_amplitude",
/// "envelope_change", "saturated", "lco": {"amplitude", "amplitude_spread", "frequency_hz",
/// "frequency_spread", "cycles"} or null, "peak_times", "peak_values". Numbers that are not
/// finite are written as null.
std::string response_to_json(const ResponseAnalysis& a, std::string_view probe);

}  // namespace shellflow::coupling
