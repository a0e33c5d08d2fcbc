#pragma once
// Scalar functions of time that scale loads and prescribed motions: f(t) and f'(t).
#include <optional>
#include <string>
#include <vector>

#include "shellflow/core/expression.h"

namespace shellflow {

class TimeFunction {
 public:
  enum class Kind { constant, ramp, sine, tabulated, step, smooth_step, expression };

  /// f(t) = value.
  static TimeFunction constant(double value);
  /// f(t) = value * min(t / duration, 1) (duration > 0).
  static TimeFunction ramp(double value, double duration);
  /// f(t) = value * sin(2 pi frequency t + phase).
  static TimeFunction sine(double value, double frequency, double phase = 0.0);
  /// Piecewise linear through (times[i], values[i]), constant outside; times increasing.
  static TimeFunction tabulated(std::vector<double> times, std::vector<double> values);
  /// f(t) = 0 for t < t_on, value for t >= t_on. f'(t) = 0 everywhere, not the impulse
  /// value * delta(t - t_on): no double holds it (see derivative()); use smooth_step where
  /// the rate matters.
  static TimeFunction step(double value, double t_on);
  /// f(t) = value * s^2 (3 - 2 s), s = clamp((t - t_on) / duration, 0, 1) (duration > 0):
  /// from 0 at t_on to value at t_on + duration with f' continuous (zero at both ends).
  static TimeFunction smooth_step(double value, double t_on, double duration);
  /// f(t) given by an arithmetic expression in t (see expression.h for the language), e.g.
  /// "0.1*sin(2*pi*20*t)"; throws InputError naming the column of a syntax error.
  static TimeFunction expression(std::string text);

  /// f(t). On a named function (named()) a result that is not finite throws InputError.
  double value(double t) const;
  /// df/dt; at a kink (ramp start and end, table points) the right derivative, the rate
  /// a motion starting at t has. Checked like value() on a named function.
  double derivative(double t) const;
  Kind kind() const { return kind_; }

  /// The same function, named for messages by `where` (the case-file key it was read from,
  /// e.g. `case.yaml:31: motion.prescribed.modes[0].amplitude`), whose value() and
  /// derivative() check their result: one that is not finite throws InputError
  /// `WHERE: is NaN at t = 0.1003 s (sqrt of a negative number?); the expression must stay
  /// finite over the run`. The check sits here, where every load and prescribed motion reads
  /// its function, so that a NaN stops the run with its cause instead of reaching a solver.
  TimeFunction named(std::string where) const {
    TimeFunction f = *this;
    f.where_ = std::move(where);
    return f;
  }
  const std::string& where() const { return where_; }
  /// f(t) + offset (same derivative), e.g. a pressure history relative to a reference.
  TimeFunction shifted(double offset) const {
    TimeFunction f = *this;
    f.offset_ += offset;
    return f;
  }

  /// The first of `samples` equally spaced times in [t0, t1] (both ends included) where
  /// f or f' is not finite (an expression dividing by zero, log of a negative number ...),
  /// or none. A sampling check, not a proof: a pole between two samples goes unseen.
  std::optional<double> first_non_finite(double t0, double t1, int samples = 1001) const;
  bool is_finite_on(double t0, double t1, int samples = 1001) const {
    return !first_non_finite(t0, t1, samples).has_value();
  }

 private:
  Kind kind_ = Kind::constant;
  double a_ = 0.0, b_ = 0.0, c_ = 0.0;
  double offset_ = 0.0;  ///< added to value()
  std::string where_;    ///< empty: unchecked
  double raw_value(double t) const;
  double raw_derivative(double t) const;
  [[noreturn]] void fail_non_finite(double t, double value, bool is_derivative) const;
  std::vector<double> times_, values_;
  Expression expression_;
};

}  // namespace shellflow
