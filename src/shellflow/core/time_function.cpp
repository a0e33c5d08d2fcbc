#include "shellflow/core/time_function.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "shellflow/core/error.h"

namespace shellflow {

TimeFunction TimeFunction::constant(double value) {
  TimeFunction f;
  f.kind_ = Kind::constant;
  f.a_ = value;
  return f;
}

TimeFunction TimeFunction::ramp(double value, double duration) {
  if (!(duration > 0.0)) throw InputError(fmt::format("ramp duration must be > 0, got {}", duration));
  TimeFunction f;
  f.kind_ = Kind::ramp;
  f.a_ = value;
  f.b_ = duration;
  return f;
}

TimeFunction TimeFunction::sine(double value, double frequency, double phase) {
  TimeFunction f;
  f.kind_ = Kind::sine;
  f.a_ = value;
  f.b_ = 2.0 * std::numbers::pi * frequency;
  f.c_ = phase;
  return f;
}

TimeFunction TimeFunction::tabulated(std::vector<double> times, std::vector<double> values) {
  if (times.empty() || times.size() != values.size()) {
    throw InputError("a tabulated time function needs as many times as values, at least one");
  }
  if (!std::is_sorted(times.begin(), times.end()) ||
      std::adjacent_find(times.begin(), times.end()) != times.end()) {
    throw InputError("the times of a tabulated time function must be strictly increasing");
  }
  TimeFunction f;
  f.kind_ = Kind::tabulated;
  f.times_ = std::move(times);
  f.values_ = std::move(values);
  return f;
}

double TimeFunction::value(double t) const {
  switch (kind_) {
    case Kind::constant: return a_;
    case Kind::ramp: return a_ * std::clamp(t / b_, 0.0, 1.0);
    case Kind::sine: return a_ * std::sin(b_ * t + c_);
    case Kind::tabulated: {
      if (t <= times_.front()) return values_.front();
      if (t >= times_.back()) return values_.back();
      const auto i = static_cast<std::size_t>(
          std::upper_bound(times_.begin(), times_.end(), t) - times_.begin());
      const double s = (t - times_[i - 1]) / (times_[i] - times_[i - 1]);
      return (1.0 - s) * values_[i - 1] + s * values_[i];
    }
  }
  return 0.0;
}

double TimeFunction::derivative(double t) const {
  switch (kind_) {
    case Kind::constant: return 0.0;
    case Kind::ramp: return (t > 0.0 && t < b_) ? a_ / b_ : 0.0;
    case Kind::sine: return a_ * b_ * std::cos(b_ * t + c_);
    case Kind::tabulated: {
      if (t <= times_.front() || t >= times_.back()) return 0.0;
      const auto i = static_cast<std::size_t>(
          std::upper_bound(times_.begin(), times_.end(), t) - times_.begin());
      return (values_[i] - values_[i - 1]) / (times_[i] - times_[i - 1]);
    }
  }
  return 0.0;
}

}  // namespace shellflow
