#pragma once
// A formula read from a case file (a strain energy of the invariants), parsed once into a tape of
// operations that is evaluated for any scalar: doubles, the second-order forward-mode numbers of
// formula_ad.hpp (exact first and second derivatives in the invariants) or Ceres Jets (derivatives in
// the parameters, for fits).
//
// Syntax (usual precedence, lowest first):
//   sum      := product (('+' | '-') product)*
//   product  := unary (('*' | '/') unary)*
//   unary    := ('-' | '+') unary | power             so -x^2 = -(x^2)
//   power    := primary ('^' unary)?                  so a^b^c = a^(b^c) and a^-b = a^(-b)
//   primary  := number | name | name '(' sum (',' sum)* ')' | '(' sum ')'
// Numbers are decimal (1, 0.5, 2.5e-3). Functions: exp, log (natural), sqrt, abs, pow(a, b) = a^b,
// min(a, b), max(a, b), step(x) (1 for x >= 0, else 0: a switch whose derivative is 0 on each side).
// Names are the caller's symbols (invariants and parameters); anything else is an error naming the
// character where it starts.
//
// Identical subexpressions are stored once (hash-consing), so that (I4 - 1) written twice is
// evaluated once.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace ibvalve::materials {

/// An error in a formula, at a character of its text.
class FormulaError : public std::runtime_error {
 public:
  FormulaError(std::size_t position, const std::string& message);
  /// 0-based index of the character in the formula's text.
  std::size_t position() const { return position_; }

 private:
  std::size_t position_;
};

enum class FormulaOp : std::uint8_t {
  constant,
  symbol,
  add,
  subtract,
  multiply,
  divide,
  negate,
  power,
  exp,
  log,
  sqrt,
  abs,
  min,
  max,
  step
};

struct FormulaNode {
  FormulaOp op = FormulaOp::constant;
  int a = -1, b = -1;       ///< operand nodes (always earlier in the tape)
  int symbol = -1;          ///< the symbol's index, for FormulaOp::symbol
  double value = 0.0;       ///< the number, for FormulaOp::constant
  std::size_t position = 0; ///< where the node starts in the text
};

class Formula {
 public:
  /// Parses `text`, whose names are `symbols` (a name's index there is its node's `symbol`).
  /// Throws FormulaError.
  Formula(std::string text, std::vector<std::string> symbols);

  const std::string& text() const { return text_; }
  const std::vector<std::string>& symbols() const { return symbols_; }
  /// Operands before their users; the last node is the formula's value.
  std::span<const FormulaNode> nodes() const { return nodes_; }
  /// Where `symbol` is first read in the text, or npos when it is never read.
  std::size_t first_use(int symbol) const;
  bool uses(int symbol) const { return first_use(symbol) != std::string::npos; }
  /// For each node, whether its value depends on one of `symbols` (the others being constants).
  std::vector<bool> depends_on(std::span<const int> symbols) const;

  /// The formula's value with `values[i]` for symbol i. T needs + - * / and, found by argument-dependent
  /// lookup or in std, exp, log, sqrt, pow, abs and the comparison <.
  template <class T>
  T evaluate(std::span<const T> values) const;
  /// The same with a buffer for every node's value (resized as needed), so that a caller evaluating
  /// many times allocates once.
  template <class T>
  T evaluate(std::span<const T> values, std::vector<T>& scratch) const;

 private:
  friend class FormulaParser;
  int add_node(const FormulaNode& node);

  std::string text_;
  std::vector<std::string> symbols_;
  std::vector<FormulaNode> nodes_;
};

/// a^b for a constant exponent b: repeated products when b is a small integer (exact for b = 2, as
/// the built-in laws compute it, and defined for a <= 0), otherwise pow.
template <class T>
T formula_power(const T& a, double b)
{
  using std::pow;
  const double n = b < 0.0 ? -b : b;
  if (n == static_cast<double>(static_cast<int>(n)) && n <= 16.0) {
    T result(1.0), base = a;
    bool empty = true; // result is still 1: the first factor is copied, not multiplied
    for (int k = static_cast<int>(n); k > 0; k >>= 1) {
      if (k & 1) result = empty ? base : result * base, empty = false;
      if (k > 1) base = base * base;
    }
    return b < 0.0 ? T(1.0) / result : result;
  }
  return pow(a, b);
}

template <class T>
T Formula::evaluate(std::span<const T> values) const
{
  std::vector<T> scratch;
  return evaluate(values, scratch);
}

template <class T>
T Formula::evaluate(std::span<const T> values, std::vector<T>& v) const
{
  using std::exp, std::log, std::sqrt;
  v.resize(nodes_.size());
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const FormulaNode& n = nodes_[i];
    const auto a = static_cast<std::size_t>(n.a), b = static_cast<std::size_t>(n.b);
    switch (n.op) {
    case FormulaOp::constant:
      v[i] = T(n.value);
      break;
    case FormulaOp::symbol:
      v[i] = values[static_cast<std::size_t>(n.symbol)];
      break;
    case FormulaOp::add:
      v[i] = v[a] + v[b];
      break;
    case FormulaOp::subtract:
      v[i] = v[a] - v[b];
      break;
    case FormulaOp::multiply:
      v[i] = v[a] * v[b];
      break;
    case FormulaOp::divide:
      v[i] = v[a] / v[b];
      break;
    case FormulaOp::negate:
      v[i] = -v[a];
      break;
    case FormulaOp::power:
      if constexpr (std::is_same_v<T, double>)
        v[i] = formula_power(v[a], v[b]); // also a whole exponent held in a parameter
      else if (nodes_[b].op == FormulaOp::constant)
        v[i] = formula_power(v[a], nodes_[b].value);
      else
        v[i] = exp(v[b] * log(v[a])); // a^b = e^(b ln a) for a > 0
      break;
    case FormulaOp::exp:
      v[i] = exp(v[a]);
      break;
    case FormulaOp::log:
      v[i] = log(v[a]);
      break;
    case FormulaOp::sqrt:
      v[i] = sqrt(v[a]);
      break;
    case FormulaOp::abs:
      v[i] = v[a] < T(0.0) ? -v[a] : v[a];
      break;
    case FormulaOp::min:
      v[i] = v[b] < v[a] ? v[b] : v[a];
      break;
    case FormulaOp::max:
      v[i] = v[a] < v[b] ? v[b] : v[a];
      break;
    case FormulaOp::step:
      v[i] = v[a] < T(0.0) ? T(0.0) : T(1.0);
      break;
    }
  }
  return v.back();
}

} // namespace ibvalve::materials
