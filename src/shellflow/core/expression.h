#pragma once
// A small arithmetic language for functions written in a case file, by default of the time t
// (time functions), or of any named variables (x, y, z, t for fields in space and time):
//   numbers (2, 0.5, .5, 1e-3), the variables, the constants pi and e, + - * / ^, parentheses,
//   sin cos tan exp log sqrt abs tanh step (one argument), min max pow atan2 (two).
// Precedence as in mathematics: ^ binds tighter than a sign and is right-associative
// (-t^2 = -(t^2), 2^3^2 = 2^9, 2^-t = 2^(-t)); * / before + -, both left-associative.
// step(s) is 0 for s < 0 and 1 for s >= 0; log is the natural logarithm.
// The text is parsed once into postfix code (constant parts folded), so that an evaluation
// is a short loop over that code; derivatives are exact, by forward-mode automatic
// differentiation (dual numbers) over the same code.
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace shellflow {

class Expression {
 public:
  struct ValueAndDerivative {
    double value = 0.0;
    double derivative = 0.0;
  };

  /// The expression 0, of no variables.
  Expression();

  /// Parses `text`, an expression of t; throws InputError naming the column (1-based, in
  /// bytes) and what was expected, e.g. `expression "sin(2*pi*t": column 11: expected ')'`.
  static Expression parse(std::string_view text);
  /// Parses an expression of `variables` (names, none of them pi, e or a function name);
  /// evaluations take their values in this order.
  static Expression parse(std::string_view text, std::span<const std::string_view> variables);

  // Evaluation raises no arithmetic error: it follows IEEE arithmetic, so x/0 is ±inf, 0/0
  // and log(-1) are NaN; callers that need finite values check them (std::isfinite,
  // TimeFunction::is_finite_on). Where a derivative does not exist, the mean of the one-sided
  // ones is returned (abs at 0, min and max at a tie), and 0 for step (its Dirac impulse
  // cannot be represented).

  /// The value of an expression of one variable (t) at t.
  double value(double t) const { return value(std::span<const double>(&t, 1)); }
  /// d/dt of an expression of one variable at t.
  double derivative(double t) const { return evaluate(t).derivative; }
  ValueAndDerivative evaluate(double t) const { return evaluate(std::span<const double>(&t, 1), 0); }

  /// The value at `point`: one value per variable, in the order given to parse() (fewer
  /// values than variables is a programming error: std::invalid_argument).
  double value(std::span<const double> point) const;
  /// The value and the partial derivative with respect to variable number `variable`.
  ValueAndDerivative evaluate(std::span<const double> point, std::size_t variable) const;

  /// Why the expression is not finite at `point` (its value, and with `variable` >= 0 its
  /// derivative with respect to that variable too): the first operation that turns finite
  /// operands into a non-finite result, e.g. "sqrt of a negative number", "division by zero",
  /// "overflow in a product"; empty when it is finite there or a variable is not finite.
  /// For messages only: it parses the text again (without constant folding).
  std::string explain_non_finite(std::span<const double> point, int variable = -1) const;
  std::string explain_non_finite(double t, int variable = -1) const {
    return explain_non_finite(std::span<const double>(&t, 1), variable);
  }

  const std::string& text() const { return text_; }
  const std::vector<std::string>& variables() const { return variables_; }
  /// True when the expression folded to one constant ("2*pi", not "0*t").
  bool is_constant() const { return code_.size() == 1 && code_[0].op == Op::constant; }
  /// Number of instructions after constant folding (a folded constant is one).
  std::size_t size() const { return code_.size(); }

  enum class Op : unsigned char {
    constant,  ///< pushes Instruction::constant
    variable,  ///< pushes the value of variable number Instruction::index
    negate,
    add,
    subtract,
    multiply,
    divide,
    power,
    integer_power,  ///< a^n for a constant integer n = Instruction::index, by multiplication
    sin,
    cos,
    tan,
    exp,
    log,
    sqrt,
    abs,
    tanh,
    step,
    min,
    max,
    atan2,
  };
  struct Instruction {
    Op op = Op::constant;
    int index = 0;          ///< variable number, or the exponent of an integer power
    double constant = 0.0;  ///< for Op::constant
  };

 private:
  friend class ExpressionParser;
  std::string text_;
  std::vector<std::string> variables_;
  std::vector<Instruction> code_;  ///< postfix: operands before their operator
  int stack_size_ = 1;             ///< deepest evaluation stack the code needs
};

}  // namespace shellflow
