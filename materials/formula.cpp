#include "materials/formula.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <map>
#include <tuple>

namespace ibvalve::materials {

FormulaError::FormulaError(std::size_t position, const std::string& message)
    : std::runtime_error(message), position_(position)
{
}

namespace {

struct FunctionSpec {
  std::string_view name;
  FormulaOp op;
  int arguments;
};

constexpr std::array<FunctionSpec, 8> functions{{
    {"exp", FormulaOp::exp, 1},
    {"log", FormulaOp::log, 1},
    {"sqrt", FormulaOp::sqrt, 1},
    {"abs", FormulaOp::abs, 1},
    {"step", FormulaOp::step, 1},
    {"pow", FormulaOp::power, 2},
    {"min", FormulaOp::min, 2},
    {"max", FormulaOp::max, 2},
}};

std::string function_names()
{
  std::string names;
  for (const auto& f : functions) names += (names.empty() ? "" : ", ") + std::string(f.name);
  return names;
}

bool is_name_start(char c)
{
  return std::isalpha(static_cast<unsigned char>(c)) || c == '_';
}

bool is_name_char(char c)
{
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
}

} // namespace

/// Recursive descent over the grammar in formula.hpp; each rule returns the index of its node.
class FormulaParser {
 public:
  explicit FormulaParser(Formula& formula) : f_(formula), text_(formula.text_) {}

  void parse()
  {
    skip_space();
    if (at_end()) throw FormulaError(0, "empty formula");
    const int root = sum();
    skip_space();
    if (!at_end()) throw FormulaError(pos_, "unexpected '" + std::string(1, text_[pos_]) + "'");
    // The root is built after every node it reads, and no earlier node can equal it, so it is last.
    if (root != static_cast<int>(f_.nodes_.size()) - 1) throw std::logic_error("Formula: root not last");
  }

 private:
  int sum()
  {
    int left = product();
    for (skip_space(); !at_end() && (peek() == '+' || peek() == '-'); skip_space()) {
      const std::size_t at = pos_;
      const FormulaOp op = text_[pos_++] == '+' ? FormulaOp::add : FormulaOp::subtract;
      left = binary(op, left, product(), at);
    }
    return left;
  }

  int product()
  {
    int left = unary();
    for (skip_space(); !at_end() && (peek() == '*' || peek() == '/'); skip_space()) {
      const std::size_t at = pos_;
      const FormulaOp op = text_[pos_++] == '*' ? FormulaOp::multiply : FormulaOp::divide;
      if (!at_end() && peek() == '*')
        throw FormulaError(pos_, "'**' is not an operator (write ^ for powers)");
      left = binary(op, left, unary(), at);
    }
    return left;
  }

  int unary()
  {
    skip_space();
    if (!at_end() && (peek() == '-' || peek() == '+')) {
      const std::size_t at = pos_;
      const bool minus = text_[pos_++] == '-';
      const int operand = unary();
      if (!minus) return operand;
      const FormulaNode& n = f_.nodes_[static_cast<std::size_t>(operand)];
      if (n.op == FormulaOp::constant) // -2 is the number -2, so that x^-2 is a whole power
        return f_.add_node({FormulaOp::constant, -1, -1, -1, -n.value, at});
      return f_.add_node({FormulaOp::negate, operand, -1, -1, 0.0, at});
    }
    return power();
  }

  int power()
  {
    const int base = primary();
    skip_space();
    if (at_end() || peek() != '^') return base;
    const std::size_t at = pos_++;
    return binary(FormulaOp::power, base, unary(), at);
  }

  int primary()
  {
    skip_space();
    if (at_end()) throw FormulaError(pos_, "the formula ends where a number, a name or '(' is expected");
    const std::size_t start = pos_;
    const char c = peek();
    if (c == '(') {
      ++pos_;
      const int inner = sum();
      expect(')', start);
      return inner;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') return number();
    if (is_name_start(c)) return name();
    throw FormulaError(pos_,
                       "unexpected '" + std::string(1, c) + "' where a number, a name or '(' is expected");
  }

  int number()
  {
    const std::size_t start = pos_;
    double value = 0.0;
    const char* begin = text_.data() + pos_;
    const auto [end, error] = std::from_chars(begin, text_.data() + text_.size(), value);
    if (error != std::errc() || !std::isfinite(value)) throw FormulaError(start, "malformed number");
    pos_ += static_cast<std::size_t>(end - begin);
    if (!at_end() && is_name_char(peek()))
      throw FormulaError(pos_, "a name right after a number (write * for a product)");
    return f_.add_node({FormulaOp::constant, -1, -1, -1, value, start});
  }

  int name()
  {
    const std::size_t start = pos_;
    while (!at_end() && is_name_char(peek())) ++pos_;
    const std::string word = text_.substr(start, pos_ - start);
    skip_space();
    if (!at_end() && peek() == '(') return call(word, start);
    const auto& symbols = f_.symbols_;
    const auto it = std::find(symbols.begin(), symbols.end(), word);
    if (it == symbols.end()) {
      std::string known;
      for (const auto& s : symbols) known += (known.empty() ? "" : ", ") + s;
      throw FormulaError(start, "unknown symbol '" + word + "' (known: " + known + ")");
    }
    return f_.add_node({FormulaOp::symbol, -1, -1, static_cast<int>(it - symbols.begin()), 0.0, start});
  }

  int call(const std::string& word, std::size_t start)
  {
    const auto spec = std::find_if(functions.begin(), functions.end(),
                                   [&](const FunctionSpec& f) { return f.name == word; });
    if (spec == functions.end())
      throw FormulaError(start, "unknown function '" + word + "' (functions: " + function_names() + ")");
    ++pos_; // '('
    std::array<int, 2> args{-1, -1};
    for (int k = 0; k < spec->arguments; ++k) {
      if (k > 0) expect(',', start);
      args[static_cast<std::size_t>(k)] = sum();
    }
    skip_space();
    if (!at_end() && peek() == ',')
      throw FormulaError(pos_, word + "() takes " + std::to_string(spec->arguments) + " argument" +
                                   (spec->arguments > 1 ? "s" : ""));
    expect(')', start);
    return f_.add_node({spec->op, args[0], args[1], -1, 0.0, start});
  }

  /// A binary operation, placed at its operator (where a division by zero or a bad power is).
  int binary(FormulaOp op, int a, int b, std::size_t at) { return f_.add_node({op, a, b, -1, 0.0, at}); }

  void expect(char c, std::size_t opened_at)
  {
    skip_space();
    if (at_end())
      throw FormulaError(opened_at, std::string("'") + c + "' missing: the formula ends before it");
    if (peek() != c)
      throw FormulaError(pos_, std::string("expected '") + c + "', found '" + std::string(1, peek()) + "'");
    ++pos_;
  }

  void skip_space()
  {
    while (!at_end() && std::isspace(static_cast<unsigned char>(peek()))) ++pos_;
  }
  bool at_end() const { return pos_ >= text_.size(); }
  char peek() const { return text_[pos_]; }

  Formula& f_;
  const std::string& text_;
  std::size_t pos_ = 0;
};

Formula::Formula(std::string text, std::vector<std::string> symbols)
    : text_(std::move(text)), symbols_(std::move(symbols))
{
  FormulaParser parser(*this);
  parser.parse();
}

int Formula::add_node(const FormulaNode& node)
{
  // Hash-consing: an operation already on the tape with the same operands is reused. A repeated
  // node keeps the position where it first appeared.
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const FormulaNode& n = nodes_[i];
    if (n.op == node.op && n.a == node.a && n.b == node.b && n.symbol == node.symbol &&
        (node.op != FormulaOp::constant || n.value == node.value))
      return static_cast<int>(i);
  }
  nodes_.push_back(node);
  return static_cast<int>(nodes_.size() - 1);
}

std::size_t Formula::first_use(int symbol) const
{
  std::size_t first = std::string::npos;
  for (const FormulaNode& n : nodes_)
    if (n.op == FormulaOp::symbol && n.symbol == symbol) first = std::min(first, n.position);
  return first;
}

std::vector<bool> Formula::depends_on(std::span<const int> symbols) const
{
  std::vector<bool> out(nodes_.size(), false);
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const FormulaNode& n = nodes_[i];
    if (n.op == FormulaOp::symbol)
      out[i] = std::find(symbols.begin(), symbols.end(), n.symbol) != symbols.end();
    else
      out[i] = (n.a >= 0 && out[static_cast<std::size_t>(n.a)]) ||
               (n.b >= 0 && out[static_cast<std::size_t>(n.b)]);
  }
  return out;
}

} // namespace ibvalve::materials
