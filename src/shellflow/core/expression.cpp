#include "shellflow/core/expression.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "shellflow/core/error.h"
#include "shellflow/core/expression_eval.h"

namespace shellflow {
namespace {

using expression_detail::apply;
using expression_detail::arity;
using expression_detail::Dual;
using expression_detail::run;
using Op = Expression::Op;

struct Function {
  std::string_view name;
  Op op;
  int arguments;
};
constexpr std::array<Function, 13> kFunctions = {{
    {"sin", Op::sin, 1},
    {"cos", Op::cos, 1},
    {"tan", Op::tan, 1},
    {"exp", Op::exp, 1},
    {"log", Op::log, 1},
    {"sqrt", Op::sqrt, 1},
    {"abs", Op::abs, 1},
    {"tanh", Op::tanh, 1},
    {"step", Op::step, 1},
    {"min", Op::min, 2},
    {"max", Op::max, 2},
    {"pow", Op::power, 2},
    {"atan2", Op::atan2, 2},
}};

constexpr std::string_view kFunctionNames = "sin cos tan exp log sqrt abs tanh step min max pow atan2";

bool is_name_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) != 0 || c == '_'; }
bool is_name_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_'; }
bool is_digit(char c) { return c >= '0' && c <= '9'; }

constexpr std::array<std::string_view, 1> kTime = {"t"};

}  // namespace

// Recursive descent, one function per precedence level, emitting postfix code as it goes:
//   sum     := product (('+' | '-') product)*
//   product := signed (('*' | '/') signed)*
//   signed  := ('-' | '+') signed | power
//   power   := primary ('^' signed)?            right-associative, exponent may be signed
//   primary := number | variable | 'pi' | 'e' | function '(' sum (',' sum)* ')' | '(' sum ')'
class ExpressionParser {
 public:
  /// `fold` false keeps constant parts as they are written (for explain_non_finite).
  ExpressionParser(std::string_view text, std::span<const std::string_view> variables, bool fold = true)
      : text_(text), variables_(variables.begin(), variables.end()), fold_(fold) {
    for (std::size_t i = 0; i < variables_.size(); ++i) {
      const std::string_view v = variables_[i];
      const bool is_name = !v.empty() && is_name_start(v[0]) && std::all_of(v.begin(), v.end(), is_name_char);
      const bool reserved =
          v == "pi" || v == "e" ||
          std::any_of(kFunctions.begin(), kFunctions.end(), [&](const Function& f) { return f.name == v; });
      if (!is_name || reserved ||
          std::find(variables_.begin(), variables_.begin() + static_cast<std::ptrdiff_t>(i), v) !=
              variables_.begin() + static_cast<std::ptrdiff_t>(i)) {
        throw std::invalid_argument(fmt::format("'{}' cannot name a variable of an expression", v));
      }
      variable_list_ += fmt::format("{}, ", v);
    }
  }

  Expression parse() {
    parse_sum();
    if (peek() != '\0') {
      const char c = text_[pos_];
      // "2t" or "2(t+1)": say that the product needs its operator.
      const bool juxtaposed = is_name_start(c) || c == '(' || is_digit(c);
      fail(pos_, fmt::format("expected an operator (+ - * / ^) or the end of the expression, got {}{}", describe(pos_),
                             juxtaposed ? " (a product needs an explicit '*')" : ""));
    }
    Expression e;
    e.text_ = std::string(text_);
    e.variables_.assign(variables_.begin(), variables_.end());
    e.code_ = std::move(code_);
    int depth = 0;
    for (const Expression::Instruction& instruction : e.code_) {
      depth += 1 - arity(instruction.op);
      e.stack_size_ = std::max(e.stack_size_, depth);
    }
    return e;
  }

 private:
  static constexpr int kMaxNesting = 200;  // keeps the recursion far from the C++ stack limit
  static constexpr double kMaxIntegerPower = 64.0;

  void parse_sum() {
    parse_product();
    for (char c = peek(); c == '+' || c == '-'; c = peek()) {
      ++pos_;
      parse_product();
      emit(c == '+' ? Op::add : Op::subtract);
    }
  }

  void parse_product() {
    parse_signed();
    for (char c = peek(); c == '*' || c == '/'; c = peek()) {
      ++pos_;
      parse_signed();
      emit(c == '*' ? Op::multiply : Op::divide);
    }
  }

  void parse_signed() {
    const char c = peek();
    if (++nesting_ > kMaxNesting) fail(pos_, fmt::format("nested deeper than {} levels", kMaxNesting));
    if (c == '-' || c == '+') {
      ++pos_;
      parse_signed();
      if (c == '-') emit(Op::negate);
    } else {
      parse_power();
    }
    --nesting_;
  }

  void parse_power() {
    parse_primary();
    if (peek() == '^') {
      ++pos_;
      parse_signed();
      emit(Op::power);
    }
  }

  void parse_primary() {
    const char c = peek();
    if (c == '(') {
      ++pos_;
      parse_sum();
      expect(')');
      return;
    }
    if (is_digit(c) || (c == '.' && pos_ + 1 < text_.size() && is_digit(text_[pos_ + 1]))) {
      parse_number();
      return;
    }
    if (!is_name_start(c)) {
      fail(pos_, fmt::format("expected a number, {}pi, e, a function or '('{}", variable_list_,
                             c == '\0' ? std::string() : ", got " + describe(pos_)));
    }
    const std::size_t start = pos_;
    while (pos_ < text_.size() && is_name_char(text_[pos_])) ++pos_;
    const std::string_view name = text_.substr(start, pos_ - start);
    for (std::size_t i = 0; i < variables_.size(); ++i) {
      if (variables_[i] == name) return code_.push_back({Op::variable, static_cast<int>(i), 0.0});
    }
    if (name == "pi") return emit_constant(std::numbers::pi);
    if (name == "e") return emit_constant(std::numbers::e);
    for (const Function& f : kFunctions) {
      if (f.name != name) continue;
      expect('(', fmt::format(" after '{}'", name));
      // The argument count is worth saying only when a ',' or ')' came early or late.
      const std::string count =
          fmt::format(" ({} takes {} argument{})", name, f.arguments, f.arguments == 1 ? "" : "s");
      for (int i = 0; i < f.arguments; ++i) {
        if (i > 0) expect(',', {}, peek() == ')' ? count : std::string());
        parse_sum();
      }
      expect(')', {}, peek() == ',' ? count : std::string());
      return emit(f.op);
    }
    fail(start,
         fmt::format("unknown name '{}'; expected {}pi, e or a function {}", name, variable_list_, kFunctionNames));
  }

  // digits [. digits] [(e|E) [+|-] digits], or . digits [...]; an 'e' not followed by an
  // exponent is left for the name rule, so that "2e" reads as 2 then the constant e.
  void parse_number() {
    const std::size_t start = pos_;
    while (pos_ < text_.size() && is_digit(text_[pos_])) ++pos_;
    if (pos_ < text_.size() && text_[pos_] == '.') {
      ++pos_;
      while (pos_ < text_.size() && is_digit(text_[pos_])) ++pos_;
    }
    if (pos_ < text_.size() && (text_[pos_] == 'e' || text_[pos_] == 'E')) {
      std::size_t p = pos_ + 1;
      if (p < text_.size() && (text_[p] == '+' || text_[p] == '-')) ++p;
      if (p < text_.size() && is_digit(text_[p])) {
        pos_ = p;
        while (pos_ < text_.size() && is_digit(text_[pos_])) ++pos_;
      }
    }
    double value = 0.0;
    const auto [end, error] = std::from_chars(text_.data() + start, text_.data() + pos_, value);
    if (error != std::errc() || end != text_.data() + pos_) {
      fail(start, fmt::format("number '{}' is out of the range of a double", text_.substr(start, pos_ - start)));
    }
    emit_constant(value);
  }

  // `after` and `note` complete the message: "expected '(' after 'sin', got 't'",
  // "expected ',', got ')' (min takes 2 arguments)".
  void expect(char c, std::string_view after = {}, std::string_view note = {}) {
    if (peek() != c) {
      fail(pos_, fmt::format("expected '{}'{}{}{}", c, after,
                             pos_ < text_.size() ? ", got " + describe(pos_) : std::string(), note));
    }
    ++pos_;
  }

  // The next character after blanks, '\0' at the end.
  char peek() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_])) != 0) ++pos_;
    return pos_ < text_.size() ? text_[pos_] : '\0';
  }

  // The token at `pos` for a message: a whole name or number, else one character (all the
  // bytes of a UTF-8 one, such as a pasted '−' or '·').
  std::string describe(std::size_t pos) const {
    std::size_t end = pos + 1;
    if (is_name_char(text_[pos]) || text_[pos] == '.') {
      while (end < text_.size() && (is_name_char(text_[end]) || text_[end] == '.')) ++end;
    } else if ((static_cast<unsigned char>(text_[pos]) & 0xC0u) == 0xC0u) {
      while (end < text_.size() && (static_cast<unsigned char>(text_[end]) & 0xC0u) == 0x80u) ++end;
    }
    return fmt::format("'{}'", text_.substr(pos, end - pos));
  }

  [[noreturn]] void fail(std::size_t pos, std::string_view what) const {
    throw_input_error("expression \"{}\": column {}: {}", text_, pos + 1, what);
  }

  void emit_constant(double value) { code_.push_back({Op::constant, 0, value}); }

  // Appends `op`; if all its operands are constants, replaces them by the result, so that
  // 2*pi*20 costs nothing per evaluation. In postfix code the operands of the last operator
  // are constants exactly when the last `arity` instructions are.
  void emit(Op op) {
    // a^n with a constant small integer n: one unary instruction instead of a call to pow.
    if (op == Op::power && code_.back().op == Op::constant) {
      const double n = code_.back().constant;
      if (n == std::trunc(n) && std::abs(n) <= kMaxIntegerPower && code_.size() >= 2 &&
          code_[code_.size() - 2].op != Op::constant) {
        code_.back() = {Op::integer_power, static_cast<int>(n), 0.0};
        return;
      }
    }
    const auto n = static_cast<std::size_t>(arity(op));
    bool constant = fold_ && code_.size() >= n;
    for (std::size_t i = 0; constant && i < n; ++i) constant = code_[code_.size() - 1 - i].op == Op::constant;
    if (!constant) {
      code_.push_back({op, 0, 0.0});
      return;
    }
    // The folded value comes from the same code as a run-time one would.
    std::vector<Expression::Instruction> folded(code_.end() - static_cast<std::ptrdiff_t>(n), code_.end());
    folded.push_back({op, 0, 0.0});
    code_.resize(code_.size() - n);
    emit_constant(run<double>(folded, 2, {}, 0));
  }

  std::string_view text_;
  std::vector<std::string_view> variables_;
  std::string variable_list_;  // "x, y, z, t, " for messages
  bool fold_ = true;
  std::size_t pos_ = 0;
  int nesting_ = 0;
  std::vector<Expression::Instruction> code_;
};

Expression::Expression() : text_("0"), code_{{Op::constant, 0, 0.0}} {}

Expression Expression::parse(std::string_view text) { return parse(text, kTime); }

Expression Expression::parse(std::string_view text, std::span<const std::string_view> variables) {
  return ExpressionParser(text, variables).parse();
}

namespace {
void check_point(std::span<const double> point, const std::vector<std::string>& variables) {
  if (point.size() < variables.size()) {
    throw std::invalid_argument(
        fmt::format("an expression of {} variables evaluated at {} values", variables.size(), point.size()));
  }
}
}  // namespace

double Expression::value(std::span<const double> point) const {
  check_point(point, variables_);
  return run<double>(code_, stack_size_, point, 0);
}

namespace {

bool finite(const Dual& a) { return std::isfinite(a.v) && std::isfinite(a.d); }

// What `op` did to the finite operands a (and b) to give the non-finite r.
std::string cause(Op op, const Dual& a, const Dual& b, const Dual& r) {
  if (std::isfinite(r.v)) {  // only the derivative
    switch (op) {
      case Op::sqrt:
        return "sqrt of 0, whose slope is infinite";
      case Op::power:
      case Op::integer_power:
        return "a power of 0 below 1, whose slope is infinite";
      case Op::log:
        return "log of 0";
      case Op::divide:
        return "division by zero";
      default:
        return "an operation whose slope is infinite there";
    }
  }
  switch (op) {
    case Op::sqrt:
      return "sqrt of a negative number";
    case Op::log:
      return a.v == 0.0 ? "log of 0" : "log of a negative number";
    case Op::divide:
      return b.v == 0.0 ? "division by zero" : "overflow in a division";
    case Op::power:
      if (a.v == 0.0 && b.v < 0.0) return "0 to a negative power";
      if (a.v < 0.0 && b.v != std::trunc(b.v)) return "a negative number to a non-integer power";
      return "overflow in a power";
    case Op::integer_power:
      return a.v == 0.0 ? "0 to a negative power" : "overflow in a power";
    case Op::exp:
      return "overflow in exp";
    case Op::tan:
      return "tan at a pole";
    case Op::multiply:
      return "overflow in a product";
    case Op::add:
    case Op::subtract:
      return "overflow in a sum";
    default:
      return "an operation out of its range";
  }
}

}  // namespace

std::string Expression::explain_non_finite(std::span<const double> point, int variable) const {
  check_point(point, variables_);
  // Unfolded code, so that a constant part such as sqrt(-1) is seen as the sqrt it is.
  std::vector<std::string_view> names(variables_.begin(), variables_.end());
  const Expression plain = ExpressionParser(text_, names, false).parse();
  std::vector<Dual> stack(static_cast<std::size_t>(plain.stack_size_) + 1);
  Dual* top = stack.data();
  for (const Instruction& in : plain.code_) {
    const int n = arity(in.op);
    const Dual a = n >= 1 ? top[-n] : Dual{0.0, 0.0};
    const Dual b = n >= 2 ? top[-1] : Dual{0.0, 0.0};
    // Without a variable the derivative parts are all zero, or NaN after a division by 0.
    const auto ok = [&](const Dual& x) { return variable < 0 ? std::isfinite(x.v) : finite(x); };
    const bool operands_finite = (n < 1 || ok(a)) && (n < 2 || ok(b));
    apply<Dual>(in, point, variable, top);
    const Dual r = top[-1];
    if (operands_finite && !ok(r)) {
      if (in.op == Op::variable || in.op == Op::constant) return {};
      return cause(in.op, a, b, r);
    }
  }
  return {};
}

Expression::ValueAndDerivative Expression::evaluate(std::span<const double> point, std::size_t variable) const {
  check_point(point, variables_);
  const Dual r = run<Dual>(code_, stack_size_, point, static_cast<int>(variable));
  return {r.v, r.d};
}

}  // namespace shellflow
