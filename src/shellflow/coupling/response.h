#pragma once
// Response analysis of a probe history w(t) (a flutter run): one extremum per half-cycle
// (the largest |w| between sign changes, noise-made short half-cycles merged away),
// the growth rate sigma of their envelope |w_peak| ~ exp(sigma t) (least-squares fit of
// log|w_peak| against the peak times, with its standard error), and the frequency from the
// spacing of the extrema (half periods). Peak times and values are refined by a parabola
// through the sample and its neighbours.
#include <span>
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

}  // namespace shellflow::coupling
