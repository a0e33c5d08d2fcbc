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
  if (!std::is_sorted(times.begin(), times.end()) || std::adjacent_find(times.begin(), times.end()) != times.end()) {
    throw InputError("the times of a tabulated time function must be strictly increasing");
  }
  TimeFunction f;
  f.kind_ = Kind::tabulated;
  f.times_ = std::move(times);
  f.values_ = std::move(values);
  return f;
}

TimeFunction TimeFunction::step(double value, double t_on) {
  if (!std::isfinite(t_on)) throw InputError(fmt::format("step time must be finite, got {}", t_on));
  TimeFunction f;
  f.kind_ = Kind::step;
  f.a_ = value;
  f.b_ = t_on;
  return f;
}

TimeFunction TimeFunction::smooth_step(double value, double t_on, double duration) {
  if (!std::isfinite(t_on)) throw InputError(fmt::format("smooth step time must be finite, got {}", t_on));
  if (!(duration > 0.0) || !std::isfinite(duration)) {
    throw InputError(fmt::format("smooth step duration must be > 0 and finite, got {}", duration));
  }
  TimeFunction f;
  f.kind_ = Kind::smooth_step;
  f.a_ = value;
  f.b_ = t_on;
  f.c_ = duration;
  return f;
}

TimeFunction TimeFunction::expression(std::string text) {
  TimeFunction f;
  f.kind_ = Kind::expression;
  f.expression_ = Expression::parse(text);
  return f;
}

double TimeFunction::value(double t) const {
  const double v = raw_value(t) + offset_;
  if (!where_.empty() && !std::isfinite(v)) fail_non_finite(t, v, false);
  return v;
}

double TimeFunction::derivative(double t) const {
  const double d = raw_derivative(t);
  if (!where_.empty() && !std::isfinite(d)) fail_non_finite(t, d, true);
  return d;
}

void TimeFunction::fail_non_finite(double t, double value, bool is_derivative) const {
  const std::string what = std::isnan(value) ? "NaN" : (value > 0 ? "inf" : "-inf");
  std::string cause;
  if (kind_ == Kind::expression) cause = expression_.explain_non_finite(t, is_derivative ? 0 : -1);
  if (cause.empty() && !std::isfinite(t)) cause = "the time itself is not finite";
  throw InputError(fmt::format("{}: {} {} at t = {:.6g} s{}; the {} must stay finite over the run", where_,
                               is_derivative ? "its rate d/dt is" : "is", what, t,
                               cause.empty() ? std::string() : fmt::format(" ({}?)", cause),
                               kind_ == Kind::expression ? "expression" : "function"));
}

double TimeFunction::raw_value(double t) const {
  switch (kind_) {
    case Kind::constant:
      return a_;
    case Kind::ramp:
      return a_ * std::clamp(t / b_, 0.0, 1.0);
    case Kind::sine:
      return a_ * std::sin(b_ * t + c_);
    case Kind::tabulated: {
      if (t <= times_.front()) return values_.front();
      if (t >= times_.back()) return values_.back();
      const auto i = static_cast<std::size_t>(std::upper_bound(times_.begin(), times_.end(), t) - times_.begin());
      const double s = (t - times_[i - 1]) / (times_[i] - times_[i - 1]);
      return (1.0 - s) * values_[i - 1] + s * values_[i];
    }
    case Kind::step:
      return t >= b_ ? a_ : 0.0;
    case Kind::smooth_step: {
      const double s = std::clamp((t - b_) / c_, 0.0, 1.0);
      return a_ * s * s * (3.0 - 2.0 * s);
    }
    case Kind::expression:
      return expression_.value(t);
  }
  return 0.0;
}

double TimeFunction::raw_derivative(double t) const {
  switch (kind_) {
    case Kind::constant:
      return 0.0;
    case Kind::ramp:
      return (t >= 0.0 && t < b_) ? a_ / b_ : 0.0;
    case Kind::sine:
      return a_ * b_ * std::cos(b_ * t + c_);
    case Kind::tabulated: {
      if (t < times_.front() || t >= times_.back()) return 0.0;
      const auto i = static_cast<std::size_t>(std::upper_bound(times_.begin(), times_.end(), t) - times_.begin());
      return (values_[i] - values_[i - 1]) / (times_[i] - times_[i - 1]);
    }
    // The derivative of the jump is value * (Dirac impulse at t_on), which no double can
    // hold; returning a large finite number instead would depend on the time step and
    // inject an arbitrary impulse. Callers see the jump through value(); a load that needs
    // a finite rate uses smooth_step.
    case Kind::step:
      return 0.0;
    case Kind::smooth_step: {
      const double s = std::clamp((t - b_) / c_, 0.0, 1.0);
      return a_ * 6.0 * s * (1.0 - s) / c_;
    }
    case Kind::expression:
      return expression_.derivative(t);
  }
  return 0.0;
}

std::optional<double> TimeFunction::first_non_finite(double t0, double t1, int samples) const {
  if (!(t1 >= t0) || samples < 2) {
    throw InputError(
        fmt::format("first_non_finite needs t0 <= t1 and at least 2 samples, "
                    "got [{}, {}] and {}",
                    t0, t1, samples));
  }
  for (int i = 0; i < samples; ++i) {
    // The last sample is t1 itself, not t0 + (t1 - t0) * 1 with its rounding.
    const double t = i + 1 == samples ? t1 : t0 + (t1 - t0) * i / (samples - 1);
    if (!std::isfinite(raw_value(t) + offset_) || !std::isfinite(raw_derivative(t))) return t;
  }
  return std::nullopt;
}

}  // namespace shellflow
