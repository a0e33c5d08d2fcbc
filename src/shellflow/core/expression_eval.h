#pragma once
// Internal to Expression (expression.cpp): the evaluation of its postfix code. The operations
// on plain values and on dual numbers (value and derivative), and the stack machine that
// runs the code for either; the parser folds constants with the same machine.
#include <array>
#include <cmath>
#include <span>
#include <type_traits>
#include <vector>

#include "shellflow/core/expression.h"

namespace shellflow::expression_detail {

using Op = Expression::Op;

// ---- Plain values: the operations with semantics of their own ----------------------------

// min, max and step propagate NaN (std::fmin would drop it) so that a bad value stays visible.
inline double heaviside(double a) { return std::isnan(a) ? a : (a >= 0.0 ? 1.0 : 0.0); }
inline double minimum(double a, double b) { return (std::isnan(a) || std::isnan(b)) ? a + b : (b < a ? b : a); }
inline double maximum(double a, double b) { return (std::isnan(a) || std::isnan(b)) ? a + b : (b > a ? b : a); }

// a^n by repeated squaring: t^2 is the most common power in a load function, and std::pow
// costs several multiplications. Like std::pow, a^0 = 1 for every a.
inline double integer_power(double a, int n) {
  double result = 1.0, square = a;
  for (unsigned m = static_cast<unsigned>(n < 0 ? -n : n); m != 0; m >>= 1) {
    if ((m & 1u) != 0) result *= square;
    square *= square;
  }
  return n < 0 ? 1.0 / result : result;
}

// ---- Dual numbers: value and derivative with respect to t --------------------------------

struct Dual {
  double v;  // value
  double d;  // derivative
};

inline Dual operator-(const Dual& a) { return {-a.v, -a.d}; }
inline Dual operator+(const Dual& a, const Dual& b) { return {a.v + b.v, a.d + b.d}; }
inline Dual operator-(const Dual& a, const Dual& b) { return {a.v - b.v, a.d - b.d}; }
inline Dual operator*(const Dual& a, const Dual& b) { return {a.v * b.v, a.d * b.v + a.v * b.d}; }
inline Dual operator/(const Dual& a, const Dual& b) {
  const double q = a.v / b.v;
  return {q, (a.d - q * b.d) / b.v};
}

// f(a) with f'(a) = slope. A constant inner function contributes nothing even where f' is
// infinite (sqrt(0 * t) at 0): 0 * inf would otherwise make the derivative NaN.
inline Dual chain(double value, double slope, const Dual& a) { return {value, a.d == 0.0 ? 0.0 : slope * a.d}; }

inline Dual sin(const Dual& a) { return chain(std::sin(a.v), std::cos(a.v), a); }
inline Dual cos(const Dual& a) { return chain(std::cos(a.v), -std::sin(a.v), a); }
inline Dual tan(const Dual& a) {
  const double v = std::tan(a.v);
  return chain(v, 1.0 + v * v, a);
}
inline Dual exp(const Dual& a) {
  const double v = std::exp(a.v);
  return chain(v, v, a);
}
inline Dual log(const Dual& a) { return chain(std::log(a.v), 1.0 / a.v, a); }
inline Dual sqrt(const Dual& a) {
  const double v = std::sqrt(a.v);
  return chain(v, 0.5 / v, a);
}
// |a| has no derivative at a = 0; 0 is the mean of the one-sided slopes -1 and 1.
inline Dual abs(const Dual& a) { return chain(std::abs(a.v), a.v > 0.0 ? 1.0 : (a.v < 0.0 ? -1.0 : 0.0), a); }
inline Dual tanh(const Dual& a) {
  const double v = std::tanh(a.v);
  return chain(v, 1.0 - v * v, a);
}
// The jump's derivative is a Dirac impulse, which no number can hold: 0 everywhere, as
// TimeFunction::step.
inline Dual heaviside(const Dual& a) { return {heaviside(a.v), 0.0}; }

inline Dual pow(const Dual& a, const Dual& b) {
  // d(a^b) = b a^(b-1) a' + a^b ln(a) b'. Each term only when its factor a' or b' is
  // non-zero: t^2 at t < 0 must not meet ln(t), 2^t must not meet 0^(-1) at a = 0.
  const double v = std::pow(a.v, b.v);
  double d = 0.0;
  if (a.d != 0.0) d += b.v * std::pow(a.v, b.v - 1.0) * a.d;
  if (b.d != 0.0) d += v * std::log(a.v) * b.d;
  return {v, d};
}

inline Dual integer_power(const Dual& a, int n) {
  return chain(integer_power(a.v, n), n == 0 ? 0.0 : n * integer_power(a.v, n - 1), a);
}

// min(a, b) if `smaller`, else max(a, b). At a tie the one-sided slopes are a' and b'; their
// mean is the symmetric choice.
inline Dual select(const Dual& a, const Dual& b, bool smaller) {
  const double v = smaller ? minimum(a.v, b.v) : maximum(a.v, b.v);
  if (std::isnan(v)) return {v, v};
  if (a.v == b.v) return {v, 0.5 * (a.d + b.d)};
  return v == a.v ? a : b;
}
inline Dual minimum(const Dual& a, const Dual& b) { return select(a, b, true); }
inline Dual maximum(const Dual& a, const Dual& b) { return select(a, b, false); }

// atan2(y, x)' = (x y' - y x') / (x^2 + y^2).
inline Dual atan2(const Dual& y, const Dual& x) {
  const double v = std::atan2(y.v, x.v);
  if (y.d == 0.0 && x.d == 0.0) return {v, 0.0};
  return {v, (x.v * y.d - y.v * x.d) / (x.v * x.v + y.v * y.v)};
}

inline int arity(Op op) {
  switch (op) {
    case Op::constant:
    case Op::variable:
      return 0;
    case Op::add:
    case Op::subtract:
    case Op::multiply:
    case Op::divide:
    case Op::power:
    case Op::min:
    case Op::max:
    case Op::atan2:
      return 2;
    default:
      return 1;
  }
}

template <class T>
T make(double value, [[maybe_unused]] double derivative) {
  if constexpr (std::is_same_v<T, Dual>) {
    return Dual{value, derivative};
  } else {
    return value;
  }
}

// One instruction of the stack machine, for T = double (values) or Dual (values and the
// derivatives with respect to variable number `seed`); `top` is one past the last operand.
template <class T>
inline void apply(const Expression::Instruction& in, std::span<const double> point, int seed, T*& top) {
  // std:: for double; for Dual, argument-dependent lookup finds the overloads above.
  using std::sin, std::cos, std::tan, std::exp, std::log, std::sqrt, std::abs, std::tanh, std::pow, std::atan2;
  switch (in.op) {
    case Op::constant:
      *top++ = make<T>(in.constant, 0.0);
      break;
    case Op::variable:
      *top++ = make<T>(point[static_cast<std::size_t>(in.index)], in.index == seed ? 1.0 : 0.0);
      break;
    case Op::negate:
      top[-1] = -top[-1];
      break;
    case Op::sin:
      top[-1] = sin(top[-1]);
      break;
    case Op::cos:
      top[-1] = cos(top[-1]);
      break;
    case Op::tan:
      top[-1] = tan(top[-1]);
      break;
    case Op::exp:
      top[-1] = exp(top[-1]);
      break;
    case Op::log:
      top[-1] = log(top[-1]);
      break;
    case Op::sqrt:
      top[-1] = sqrt(top[-1]);
      break;
    case Op::abs:
      top[-1] = abs(top[-1]);
      break;
    case Op::tanh:
      top[-1] = tanh(top[-1]);
      break;
    case Op::step:
      top[-1] = heaviside(top[-1]);
      break;
    case Op::integer_power:
      top[-1] = integer_power(top[-1], in.index);
      break;
    case Op::add:
      --top;
      top[-1] = top[-1] + top[0];
      break;
    case Op::subtract:
      --top;
      top[-1] = top[-1] - top[0];
      break;
    case Op::multiply:
      --top;
      top[-1] = top[-1] * top[0];
      break;
    case Op::divide:
      --top;
      top[-1] = top[-1] / top[0];
      break;
    case Op::power:
      --top;
      top[-1] = pow(top[-1], top[0]);
      break;
    case Op::min:
      --top;
      top[-1] = minimum(top[-1], top[0]);
      break;
    case Op::max:
      --top;
      top[-1] = maximum(top[-1], top[0]);
      break;
    case Op::atan2:
      --top;
      top[-1] = atan2(top[-1], top[0]);
      break;
  }
}

// The stack machine: `stack` has room for the deepest point of `code`.
template <class T>
T run(const std::vector<Expression::Instruction>& code, std::span<const double> point, int seed, T* stack) {
  T* top = stack;  // one past the last operand
  for (const Expression::Instruction& in : code) apply<T>(in, point, seed, top);
  return stack[0];
}

template <class T>
T run(const std::vector<Expression::Instruction>& code, int stack_size, std::span<const double> point, int seed) {
  constexpr int kInline = 32;  // nesting deeper than this is rare; it costs one allocation
  if (stack_size <= kInline) {
    std::array<T, kInline> stack;  // left uninitialised: every slot is written before it is read
    return run<T>(code, point, seed, stack.data());
  }
  std::vector<T> stack(static_cast<std::size_t>(stack_size));
  return run<T>(code, point, seed, stack.data());
}

}  // namespace shellflow::expression_detail
