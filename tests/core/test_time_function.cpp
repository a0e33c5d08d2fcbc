#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "shellflow/core/error.h"
#include "shellflow/core/expression.h"
#include "shellflow/core/time_function.h"

using shellflow::Expression;
using shellflow::InputError;
using shellflow::TimeFunction;
using std::numbers::pi;

namespace {

constexpr std::array<std::string_view, 1> kTime = {"t"};

// The message of the InputError that parsing `text` throws, or "" if it parses.
std::string parse_error(const std::string& text, std::span<const std::string_view> variables = kTime) {
  try {
    Expression::parse(text, variables);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// Central difference; h small enough that the truncation error (h^2/6 f''') stays below
// 1e-7 of f' for every function below, large enough that rounding (eps f / h) does too.
template <class F>
double central_difference(const F& f, double t, double h = 1e-6) {
  return (f.value(t + h) - f.value(t - h)) / (2.0 * h);
}

}  // namespace

// ---- The kinds that existed before: one check of value and derivative each -------------

TEST(TimeFunction, ConstantHasZeroDerivative) {
  const TimeFunction f = TimeFunction::constant(2.5);
  EXPECT_EQ(f.value(-1.0), 2.5);
  EXPECT_EQ(f.value(3.0), 2.5);
  EXPECT_EQ(f.derivative(3.0), 0.0);
}

TEST(TimeFunction, RampRisesLinearlyThenHolds) {
  const TimeFunction f = TimeFunction::ramp(3.0, 2.0);
  EXPECT_EQ(f.value(-1.0), 0.0);
  EXPECT_DOUBLE_EQ(f.value(0.5), 0.75);
  EXPECT_EQ(f.value(5.0), 3.0);
  EXPECT_DOUBLE_EQ(f.derivative(0.5), 1.5);
  EXPECT_EQ(f.derivative(5.0), 0.0);
  // At the kinks the right derivative: the rate of a motion that starts there.
  EXPECT_DOUBLE_EQ(f.derivative(0.0), 1.5);
  EXPECT_EQ(f.derivative(2.0), 0.0);
  EXPECT_EQ(f.derivative(-1e-12), 0.0);
  EXPECT_THROW(TimeFunction::ramp(1.0, 0.0), InputError);
}

TEST(TimeFunction, SineValueAndDerivative) {
  const TimeFunction f = TimeFunction::sine(2.0, 5.0, 0.3);
  const double t = 0.013, w = 2.0 * pi * 5.0;
  EXPECT_DOUBLE_EQ(f.value(t), 2.0 * std::sin(w * t + 0.3));
  EXPECT_DOUBLE_EQ(f.derivative(t), 2.0 * w * std::cos(w * t + 0.3));
  EXPECT_NEAR(f.derivative(t), central_difference(f, t), 1e-7 * 2.0 * w);
}

TEST(TimeFunction, TabulatedInterpolatesLinearlyAndHoldsOutside) {
  const TimeFunction f = TimeFunction::tabulated({0.0, 1.0, 3.0}, {1.0, 3.0, 2.0});
  EXPECT_EQ(f.value(-1.0), 1.0);
  EXPECT_DOUBLE_EQ(f.value(0.25), 1.5);
  EXPECT_DOUBLE_EQ(f.value(2.0), 2.5);
  EXPECT_EQ(f.value(4.0), 2.0);
  EXPECT_DOUBLE_EQ(f.derivative(0.25), 2.0);
  EXPECT_DOUBLE_EQ(f.derivative(2.0), -0.5);
  EXPECT_EQ(f.derivative(4.0), 0.0);
  EXPECT_DOUBLE_EQ(f.derivative(0.0), 2.0);  // right derivatives at the table points
  EXPECT_DOUBLE_EQ(f.derivative(1.0), -0.5);
  EXPECT_EQ(f.derivative(3.0), 0.0);
  EXPECT_THROW(TimeFunction::tabulated({0.0, 0.0}, {1.0, 2.0}), InputError);
}

// ---- step and smooth_step ---------------------------------------------------------------

TEST(TimeFunction, StepIsZeroBeforeAndValueFromTheSwitchTimeOn) {
  const TimeFunction f = TimeFunction::step(4.0, 0.01);
  EXPECT_EQ(f.kind(), TimeFunction::Kind::step);
  EXPECT_EQ(f.value(0.0), 0.0);
  EXPECT_EQ(f.value(std::nextafter(0.01, 0.0)), 0.0);
  EXPECT_EQ(f.value(0.01), 4.0);
  EXPECT_EQ(f.value(1.0), 4.0);
  for (double t : {0.0, 0.01, 1.0}) EXPECT_EQ(f.derivative(t), 0.0) << t;
  EXPECT_THROW(TimeFunction::step(1.0, std::numeric_limits<double>::quiet_NaN()), InputError);
}

TEST(TimeFunction, SmoothStepIsCubicWithExactContinuousDerivative) {
  // Binary fractions, so that t_on + s * duration and back to s are exact.
  const double value = 2.0, t_on = 0.5, duration = 0.25;
  const TimeFunction f = TimeFunction::smooth_step(value, t_on, duration);
  EXPECT_EQ(f.value(0.0), 0.0);
  EXPECT_EQ(f.value(t_on), 0.0);
  EXPECT_DOUBLE_EQ(f.value(t_on + 0.5 * duration), 0.5 * value);
  // s = 1/4: s^2 (3 - 2 s) = 5/32; f' = value 6 s (1 - s) / duration = value 9/8 / duration.
  EXPECT_DOUBLE_EQ(f.value(t_on + 0.25 * duration), value * 5.0 / 32.0);
  EXPECT_DOUBLE_EQ(f.derivative(t_on + 0.25 * duration), value * 9.0 / 8.0 / duration);
  EXPECT_DOUBLE_EQ(f.derivative(t_on + 0.5 * duration), 1.5 * value / duration);
  EXPECT_DOUBLE_EQ(f.value(t_on + duration), value);
  EXPECT_EQ(f.value(3.0), value);
  // C^1: the derivative vanishes at both ends, approached from inside.
  EXPECT_EQ(f.derivative(t_on), 0.0);
  EXPECT_EQ(f.derivative(t_on + duration), 0.0);
  EXPECT_NEAR(f.derivative(t_on + 1e-9), 0.0, 1e-6);
  EXPECT_NEAR(f.derivative(t_on + duration - 1e-9), 0.0, 1e-6);
  for (double s : {0.1, 0.37, 0.5, 0.81}) {
    const double t = t_on + s * duration;
    EXPECT_NEAR(f.derivative(t), central_difference(f, t, 1e-7), 1e-6 * value / duration) << s;
  }
  EXPECT_THROW(TimeFunction::smooth_step(1.0, 0.0, 0.0), InputError);
  EXPECT_THROW(TimeFunction::smooth_step(1.0, 0.0, -1.0), InputError);
}

// ---- expression: values and derivatives --------------------------------------------------

TEST(Expression, ValuesAndDerivativesMatchHandComputedOnes) {
  struct Case {
    const char* text;
    double t, value, derivative;
  };
  const double e = std::numbers::e;
  const double w = 2.0 * pi * 20.0;
  const Case cases[] = {
      {"t", 2.0, 2.0, 1.0},
      {"3*t^2 - 2*t + 1", 2.0, 9.0, 10.0},
      {"0.1*sin(2*pi*20*t)", 0.01, 0.1 * std::sin(w * 0.01), 0.1 * w * std::cos(w * 0.01)},
      {"exp(-t)*cos(t)", 0.0, 1.0, -1.0},
      {"log(t)", e, 1.0, 1.0 / e},
      {"sqrt(t)", 4.0, 2.0, 0.25},
      {"t^t", 2.0, 4.0, 4.0 * (std::log(2.0) + 1.0)},
      {"2^t", 3.0, 8.0, 8.0 * std::log(2.0)},
      {"pow(t, 3)", 2.0, 8.0, 12.0},
      {"t^2", -3.0, 9.0, -6.0},  // a negative base with a constant exponent: no log(t)
      {"abs(t - 1)", 0.0, 1.0, -1.0},
      {"abs(t - 1)", 2.0, 1.0, 1.0},
      {"abs(t - 1)", 1.0, 0.0, 0.0},  // the kink: the mean of the slopes -1 and 1
      {"min(t, 1)", 0.5, 0.5, 1.0},
      {"min(t, 1)", 2.0, 1.0, 0.0},
      {"min(t, 1)", 1.0, 1.0, 0.5},  // a tie: the mean of the slopes 1 and 0
      {"max(t, 2*t)", -1.0, -1.0, 1.0},
      {"max(t, 2*t)", 1.0, 2.0, 2.0},
      {"tanh(t)", 0.0, 0.0, 1.0},
      {"tan(t)", pi / 4.0, 1.0, 2.0},
      {"atan2(t, 1)", 1.0, pi / 4.0, 0.5},
      {"atan2(1, t)", 1.0, pi / 4.0, -0.5},
      {"1/t", 2.0, 0.5, -0.25},
      {"sin(t)/t", pi / 2.0, 2.0 / pi, -4.0 / (pi * pi)},
      {"step(t - 0.5)", 0.4, 0.0, 0.0},
      {"step(t - 0.5)", 0.5, 1.0, 0.0},
      {"2*step(t)", 3.0, 2.0, 0.0},
      {"pi", 7.0, pi, 0.0},
      {"e", 7.0, e, 0.0},
      {"sqrt(0*t)", 0.0, 0.0, 0.0},  // f' = inf times a zero inner derivative is 0, not NaN
  };
  for (const Case& c : cases) {
    const Expression f = Expression::parse(c.text);
    const double scale = std::max(1.0, std::abs(c.derivative));
    EXPECT_NEAR(f.value(c.t), c.value, 1e-14 * std::max(1.0, std::abs(c.value))) << c.text << " at " << c.t;
    EXPECT_NEAR(f.derivative(c.t), c.derivative, 1e-14 * scale) << c.text << " at " << c.t;
    // One evaluation of both gives the same numbers as the two separate ones.
    const auto both = f.evaluate(c.t);
    EXPECT_EQ(both.value, f.value(c.t)) << c.text;
    EXPECT_EQ(both.derivative, f.derivative(c.t)) << c.text;
  }
}

TEST(Expression, DerivativesMatchCentralDifferences) {
  const char* texts[] = {
      "0.1*sin(2*pi*20*t)",
      "exp(-t)*cos(3*t)",
      "t^3 - 2*t^2 + t - 5",
      "t^t",
      "2^t",
      "log(1 + t^2)",
      "sqrt(1 + t)",
      "tanh(2*t - 1)",
      "atan2(sin(t), cos(2*t) + 2)",
      "pow(t, 2.5)",
      "1/(1 + t^2)",
      "tan(t/2)",
      "exp(sin(t))^2",
      "-t^2/(t + 1)",
      "abs(t - 1)*t",
      "max(t^2, t)",
      "min(cos(t), 0.5)",
      "(1 + t)^(1/t)",
      "e^(-t^2/2)/sqrt(2*pi)",
      "1e-3*t^-2",
  };
  int checked = 0;
  for (const char* text : texts) {
    const Expression f = Expression::parse(text);
    for (double t : {0.3, 0.7, 1.3, 2.1}) {
      const double exact = f.derivative(t);
      ASSERT_TRUE(std::isfinite(exact)) << text << " at " << t;
      EXPECT_NEAR(exact, central_difference(f, t), 1e-6 * std::max(1.0, std::abs(exact))) << text << " at " << t;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 80);
}

TEST(Expression, TimeFunctionOfAnExpressionEvaluatesIt) {
  const TimeFunction f = TimeFunction::expression("0.1*sin(2*pi*20*t)");
  EXPECT_EQ(f.kind(), TimeFunction::Kind::expression);
  const double w = 2.0 * pi * 20.0;
  EXPECT_NEAR(f.value(0.003), 0.1 * std::sin(w * 0.003), 1e-16);
  EXPECT_NEAR(f.derivative(0.003), 0.1 * w * std::cos(w * 0.003), 1e-13);
  // The same form as a sine time function, to rounding.
  const TimeFunction sine = TimeFunction::sine(0.1, 20.0);
  for (double t : {0.0, 0.0041, 0.02, 0.37}) {
    EXPECT_NEAR(f.value(t), sine.value(t), 1e-15) << t;
    EXPECT_NEAR(f.derivative(t), sine.derivative(t), 1e-12) << t;
  }
  EXPECT_THROW(TimeFunction::expression("sin(t"), InputError);
}

// ---- expression: the grammar ---------------------------------------------------------------

TEST(Expression, PrecedenceAndAssociativityFollowMathematics) {
  struct Case {
    const char* text;
    double t, value;
  };
  const Case cases[] = {
      {"-t^2", 3.0, -9.0},         // ^ binds tighter than the sign
      {"-2^2", 0.0, -4.0},         //
      {"(-2)^2", 0.0, 4.0},        //
      {"2^3^2", 0.0, 512.0},       // right-associative: 2^(3^2)
      {"(2^3)^2", 0.0, 64.0},      //
      {"2^-1", 0.0, 0.5},          // a signed exponent
      {"2^-t^2", 1.0, 0.5},        // 2^(-(t^2))
      {"1 - 2 - 3", 0.0, -4.0},    // left-associative
      {"8 / 4 / 2", 0.0, 1.0},     //
      {"2 + 3 * 4", 0.0, 14.0},    //
      {"(2 + 3) * 4", 0.0, 20.0},  //
      {"2 * -3", 0.0, -6.0},       //
      {"--t", 5.0, 5.0},           //
      {"+t", 5.0, 5.0},            //
      {"t - -t", 5.0, 10.0},       //
      {"2*t^2/4", 2.0, 2.0},       //
      {"-t*-t", 3.0, 9.0},         //
      {"1e-3", 0.0, 1e-3},         // numbers
      {"2E+2", 0.0, 200.0},        //
      {".5 + 1.", 0.0, 1.5},       //
      {"2*e", 0.0, 2.0 * std::numbers::e},
      {" \t( t\n+1 ) ", 1.0, 2.0},  // blanks anywhere between tokens
      {"max(min(t, 2), -1) ^ 2", 3.0, 4.0},
      {"pow(2, 3) + atan2(0, 1)", 0.0, 8.0},
  };
  for (const Case& c : cases) {
    EXPECT_DOUBLE_EQ(Expression::parse(c.text).value(c.t), c.value) << c.text;
  }
}

TEST(Expression, ConstantPartsAreFoldedOnce) {
  // 0.1, 2*pi*20, t, *, sin, *: the constant product costs nothing per evaluation.
  EXPECT_EQ(Expression::parse("0.1*sin(2*pi*20*t)").size(), 6u);
  EXPECT_EQ(Expression::parse("2*pi*20 + sqrt(4)^2").size(), 1u);
  EXPECT_DOUBLE_EQ(Expression::parse("2*pi*20 + sqrt(4)^2").value(0.0), 40.0 * pi + 4.0);
  EXPECT_EQ(Expression::parse("-(1)").size(), 1u);
  EXPECT_EQ(Expression::parse("t").size(), 1u);
  EXPECT_EQ(Expression().value(1.0), 0.0);
}

TEST(Expression, ConstantIntegerPowersAreMultipliedOutAndAgreeWithPow) {
  EXPECT_EQ(Expression::parse("t^2").size(), 2u);      // t, ^2
  EXPECT_EQ(Expression::parse("t^2.5").size(), 3u);    // t, 2.5, pow
  EXPECT_EQ(Expression::parse("t^65").size(), 3u);     // beyond the multiplied-out range
  EXPECT_EQ(Expression::parse("t^(1+1)").size(), 2u);  // the exponent is folded first
  struct Case {
    const char* text;
    double t, value, derivative;
  };
  const Case cases[] = {
      {"t^2", -3.0, 9.0, -6.0},
      {"t^-2", 2.0, 0.25, -0.25},
      {"(t - 1)^3", 3.0, 8.0, 12.0},
      {"t^0", 0.0, 1.0, 0.0},
      {"t^1", 5.0, 5.0, 1.0},
      {"t^-1", 0.0, std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()},
      {"pow(t, 3)", -2.0, -8.0, 12.0},
  };
  for (const Case& c : cases) {
    const Expression f = Expression::parse(c.text);
    EXPECT_EQ(f.value(c.t), c.value) << c.text;
    EXPECT_EQ(f.derivative(c.t), c.derivative) << c.text;
  }
  // Repeated squaring against std::pow: a few roundings, relative 1e-14 at most.
  for (int n = -64; n <= 64; ++n) {
    const Expression f = Expression::parse("t^" + std::to_string(n));
    for (double t : {1.1, -0.7, 3.0}) {
      const double exact = std::pow(t, n), slope = n * std::pow(t, n - 1);
      EXPECT_NEAR(f.value(t), exact, 1e-14 * std::abs(exact)) << n << " " << t;
      EXPECT_NEAR(f.derivative(t), slope, 1e-14 * std::abs(slope)) << n << " " << t;
    }
  }
}

TEST(Expression, DeepNestingIsEvaluatedAndTooDeepNestingRejected) {
  // 1+(1+(...(1+t)...)): each level holds one more value on the evaluation stack, past the
  // 32 kept inline.
  std::string text = "t";
  for (int i = 0; i < 150; ++i) text = "1+(" + text + ")";
  const Expression f = Expression::parse(text);
  EXPECT_EQ(f.value(0.5), 150.5);
  EXPECT_EQ(f.derivative(0.5), 1.0);

  const std::string deep = std::string(300, '(') + "t" + std::string(300, ')');
  EXPECT_EQ(parse_error(deep), "expression \"" + deep + "\": column 201: nested deeper than 200 levels");
}

TEST(Expression, ErrorsNameTheColumnAndWhatWasExpected) {
  const std::string operand = "expected a number, t, pi, e, a function or '('";
  const std::string operator_or_end = "expected an operator (+ - * / ^) or the end of the expression";
  const std::string product = " (a product needs an explicit '*')";
  struct Case {
    std::string text, message;
  };
  const Case cases[] = {
      {"sin(2*pi*t", "column 11: expected ')'"},
      {"sin(2*pi*t x", "column 12: expected ')', got 'x'"},
      {"", "column 1: " + operand},
      {"   ", "column 4: " + operand},
      {"t +", "column 4: " + operand},
      {"t^", "column 3: " + operand},
      {"*t", "column 1: " + operand + ", got '*'"},
      {"sin()", "column 5: " + operand + ", got ')'"},
      {"2*x",
       "column 3: unknown name 'x'; expected t, pi, e or a function sin cos tan exp log sqrt abs "
       "tanh step min max pow atan2"},
      {"Sin(t)",
       "column 1: unknown name 'Sin'; expected t, pi, e or a function sin cos tan exp log sqrt "
       "abs tanh step min max pow atan2"},
      {"sin t", "column 5: expected '(' after 'sin', got 't'"},
      {"step", "column 5: expected '(' after 'step'"},
      {"min(t)", "column 6: expected ',', got ')' (min takes 2 arguments)"},
      {"sin(t, 2)", "column 6: expected ')', got ',' (sin takes 1 argument)"},
      {"atan2(t, 1, 2)", "column 11: expected ')', got ',' (atan2 takes 2 arguments)"},
      {"2t", "column 2: " + operator_or_end + ", got 't'" + product},
      {"2 (t+1)", "column 3: " + operator_or_end + ", got '('" + product},
      {"pi(2)", "column 3: " + operator_or_end + ", got '('" + product},
      {"t 2", "column 3: " + operator_or_end + ", got '2'" + product},
      {"(t))", "column 4: " + operator_or_end + ", got ')'"},
      {"t # 2", "column 3: " + operator_or_end + ", got '#'"},
      {"1.2.3", "column 4: " + operator_or_end + ", got '.3'"},
      {"1e999*t", "column 1: number '1e999' is out of the range of a double"},
      // A pasted minus sign U+2212 is named whole, not as a broken first byte; the column
      // counts bytes.
      {"2 \u2212 t", "column 3: " + operator_or_end + ", got '\u2212'"},
      {"\u00b7t", "column 1: " + operand + ", got '\u00b7'"},
  };
  for (const Case& c : cases) {
    EXPECT_EQ(parse_error(c.text), "expression \"" + c.text + "\": " + c.message);
  }
}

// ---- expressions of several variables -------------------------------------------------------

TEST(Expression, SeveralVariablesTakeTheirValuesInOrderWithExactPartialDerivatives) {
  constexpr std::array<std::string_view, 4> xyzt = {"x", "y", "z", "t"};
  const Expression f = Expression::parse("x*y^2 + sin(z*t) - t", xyzt);
  EXPECT_EQ(f.variables(), (std::vector<std::string>{"x", "y", "z", "t"}));
  const double point[4] = {2.0, 3.0, 0.5, 0.4};
  const double zt = 0.5 * 0.4;
  EXPECT_DOUBLE_EQ(f.value(point), 18.0 + std::sin(zt) - 0.4);
  const double partials[4] = {9.0, 12.0, 0.4 * std::cos(zt), 0.5 * std::cos(zt) - 1.0};
  for (std::size_t i = 0; i < 4; ++i) {
    const auto r = f.evaluate(point, i);
    EXPECT_EQ(r.value, f.value(point)) << i;
    EXPECT_DOUBLE_EQ(r.derivative, partials[i]) << xyzt[i];
  }
  // Not every variable has to appear; an expression of t alone is the default.
  EXPECT_EQ(Expression::parse("2*y", xyzt).evaluate(point, 3).derivative, 0.0);
  EXPECT_TRUE(Expression::parse("1.5 + 2", xyzt).is_constant());
  EXPECT_FALSE(Expression::parse("0*x", xyzt).is_constant());
  EXPECT_EQ(Expression().value(point), 0.0);
  EXPECT_EQ(Expression::parse("t").variables(), std::vector<std::string>{"t"});

  // Messages list the variables of the expression.
  EXPECT_EQ(parse_error("x + s", xyzt),
            "expression \"x + s\": column 5: unknown name 's'; expected x, y, z, t, pi, e or a "
            "function sin cos tan exp log sqrt abs tanh step min max pow atan2");
  EXPECT_EQ(parse_error("x +", xyzt),
            "expression \"x +\": column 4: expected a number, x, y, z, t, pi, e, a function or "
            "'('");
  // Here t is not a variable.
  constexpr std::array<std::string_view, 1> x_only = {"x"};
  EXPECT_EQ(parse_error("t", x_only),
            "expression \"t\": column 1: unknown name 't'; expected x, pi, e or a function sin cos "
            "tan exp log sqrt abs tanh step min max pow atan2");

  // Programming errors: a reserved or repeated variable name, too few values.
  for (std::array<std::string_view, 2> bad :
       {std::array<std::string_view, 2>{"x", "pi"}, {"x", "sin"}, {"x", "x"}, {"x", "2y"}, {"x", ""}}) {
    EXPECT_THROW(Expression::parse("x", bad), std::invalid_argument) << bad[1];
  }
  EXPECT_THROW(f.value(0.5), std::invalid_argument);
}

// ---- non-finite values ------------------------------------------------------------------------

TEST(Expression, DivisionByZeroGivesInfinityAndIsFoundBySampling) {
  const Expression f = Expression::parse("1/t");
  EXPECT_EQ(f.value(0.0), std::numeric_limits<double>::infinity());
  EXPECT_EQ(f.value(-0.0), -std::numeric_limits<double>::infinity());
  EXPECT_TRUE(std::isnan(Expression::parse("t/t").value(0.0)));
  EXPECT_TRUE(std::isinf(Expression::parse("sqrt(t)").derivative(0.0)));  // vertical tangent

  const TimeFunction g = TimeFunction::expression("1/t");
  ASSERT_TRUE(g.first_non_finite(-1.0, 1.0, 3).has_value());
  EXPECT_EQ(*g.first_non_finite(-1.0, 1.0, 3), 0.0);
  EXPECT_FALSE(g.is_finite_on(-1.0, 1.0, 3));
  EXPECT_TRUE(g.is_finite_on(0.5, 2.0));
  // log and sqrt of negative numbers are NaN: found at the first sample.
  EXPECT_EQ(*TimeFunction::expression("sqrt(t)").first_non_finite(-1.0, 1.0), -1.0);
  EXPECT_TRUE(TimeFunction::expression("sqrt(t)").is_finite_on(0.01, 1.0));
  EXPECT_EQ(*TimeFunction::expression("log(1 - t)").first_non_finite(0.0, 2.0, 5), 1.0);
  EXPECT_TRUE(TimeFunction::sine(1.0, 3.0).is_finite_on(0.0, 10.0));
  // A NaN is carried through min, max and step rather than dropped.
  EXPECT_FALSE(TimeFunction::expression("min(log(t), 1)").is_finite_on(-1.0, 1.0, 2));
  EXPECT_FALSE(TimeFunction::expression("step(log(t))").is_finite_on(-1.0, 1.0, 2));
  EXPECT_THROW(g.first_non_finite(1.0, 0.0), InputError);
}

// The message of a named function that turns non-finite (issue 14): `WHERE: is NaN at t = ...`.
std::string non_finite_message(const TimeFunction& f, double t, bool derivative = false) {
  try {
    if (derivative) {
      (void)f.derivative(t);
    } else {
      (void)f.value(t);
    }
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(TimeFunction, NamedFunctionsThrowWithTheKeyTheTimeAndTheCause) {
  const std::string key = "case.yaml:31: motion.prescribed.modes[0].amplitude";
  const TimeFunction f = TimeFunction::expression("0.02*sqrt(0.1 - t)").named(key);
  EXPECT_EQ(f.where(), key);
  EXPECT_DOUBLE_EQ(f.value(0.0), 0.02 * std::sqrt(0.1));  // finite: unchanged
  EXPECT_EQ(non_finite_message(f, 0.1003),
            key +
                ": is NaN at t = 0.1003 s (sqrt of a negative number?); the expression must stay finite over "
                "the run");
  // At t = 0.1 the value is 0 but the rate is -inf.
  EXPECT_EQ(f.value(0.1), 0.0);
  EXPECT_EQ(non_finite_message(f, 0.1, true),
            key +
                ": its rate d/dt is -inf at t = 0.1 s (sqrt of 0, whose slope is infinite?); the expression "
                "must stay finite over the run");
  // The cause is found in constant parts too (folded when parsed), and for every operation.
  const auto cause = [&](const char* text, double t) {
    return non_finite_message(TimeFunction::expression(text).named("k"), t);
  };
  EXPECT_EQ(cause("sqrt(-1)", 0.0),
            "k: is NaN at t = 0 s (sqrt of a negative number?); the expression must stay finite over the run");
  EXPECT_NE(cause("1/(t - 1)", 1.0).find("is inf at t = 1 s (division by zero?)"), std::string::npos);
  EXPECT_NE(cause("log(t)", 0.0).find("is -inf at t = 0 s (log of 0?)"), std::string::npos);
  EXPECT_NE(cause("log(t)", -1.0).find("(log of a negative number?)"), std::string::npos);
  EXPECT_NE(cause("exp(1000*t)", 1.0).find("is inf at t = 1 s (overflow in exp?)"), std::string::npos);
  EXPECT_NE(cause("1e200*1e200*t", 1.0).find("(overflow in a product?)"), std::string::npos);
  EXPECT_NE(cause("(-2)^(t + 0.5)", 0.0).find("(a negative number to a non-integer power?)"), std::string::npos);
  EXPECT_NE(cause("t^-2", 0.0).find("(0 to a negative power?)"), std::string::npos);
  // The other kinds are checked too (without a cause); unnamed functions are not checked.
  const TimeFunction huge = TimeFunction::sine(1e308, 1e10).named("k");
  EXPECT_EQ(non_finite_message(huge, 0.0, true),
            "k: its rate d/dt is inf at t = 0 s; the function must stay finite over the run");
  EXPECT_TRUE(std::isnan(TimeFunction::expression("sqrt(-1)").value(0.0)));
  // A named copy keeps its name; first_non_finite samples without throwing.
  const TimeFunction shifted = f.shifted(1.0);
  EXPECT_EQ(shifted.where(), key);
  EXPECT_EQ(*f.first_non_finite(0.0, 0.2, 3), 0.1);
}

TEST(Expression, ExplainNonFiniteNamesTheFirstFailingOperation) {
  constexpr std::array<std::string_view, 4> xyzt = {"x", "y", "z", "t"};
  const Expression e = Expression::parse("1 + sqrt(x - 1)*log(t)", xyzt);
  const std::array<double, 4> p = {0.0, 0.0, 0.0, 1.0};
  EXPECT_EQ(e.explain_non_finite(p), "sqrt of a negative number");
  const std::array<double, 4> q = {2.0, 0.0, 0.0, 1.0};
  EXPECT_EQ(e.explain_non_finite(q), "");  // finite there
  const std::array<double, 4> r = {2.0, 0.0, 0.0, 0.0};
  EXPECT_EQ(e.explain_non_finite(r), "log of 0");
  const std::array<double, 4> nan_point = {std::nan(""), 0.0, 0.0, 1.0};
  EXPECT_EQ(e.explain_non_finite(nan_point), "");  // a variable itself is not finite
  // With a variable: the derivative too (sqrt(x - 1) at x = 1 has an infinite slope in x).
  const std::array<double, 4> s = {1.0, 0.0, 0.0, 2.0};
  EXPECT_EQ(e.explain_non_finite(s), "");
  EXPECT_EQ(e.explain_non_finite(s, 0), "sqrt of 0, whose slope is infinite");
}
