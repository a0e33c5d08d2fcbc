#pragma once
// Scalar functions of time that scale loads and prescribed motions: f(t) and f'(t).
#include <string>
#include <vector>

namespace shellflow {

class TimeFunction {
 public:
  enum class Kind { constant, ramp, sine, tabulated };

  /// f(t) = value.
  static TimeFunction constant(double value);
  /// f(t) = value * min(t / duration, 1) (duration > 0).
  static TimeFunction ramp(double value, double duration);
  /// f(t) = value * sin(2 pi frequency t + phase).
  static TimeFunction sine(double value, double frequency, double phase = 0.0);
  /// Piecewise linear through (times[i], values[i]), constant outside; times increasing.
  static TimeFunction tabulated(std::vector<double> times, std::vector<double> values);

  double value(double t) const;
  double derivative(double t) const;
  Kind kind() const { return kind_; }

 private:
  Kind kind_ = Kind::constant;
  double a_ = 0.0, b_ = 0.0, c_ = 0.0;
  std::vector<double> times_, values_;
};

}  // namespace shellflow
