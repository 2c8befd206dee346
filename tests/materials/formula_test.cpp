// The formula parser and its evaluators as a library (materials/formula.hpp, formula_ad.hpp,
// formula_program.hpp): the grammar's precedence and associativity, the functions, one error per
// mistake at the character where it is, and exact first and second derivatives against the
// derivatives worked out by hand.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "materials/formula.hpp"
#include "materials/formula_ad.hpp"
#include "materials/formula_program.hpp"

namespace ibvalve::materials {
namespace {

const std::vector<std::string> symbols{"a", "b", "c", "x", "y"};

double value_of(const std::string& text, std::vector<double> values = {2.0, 3.0, 2.0, 0.5, 1.5})
{
  return Formula(text, symbols).evaluate<double>(values);
}

/// The character (0-based) where `text` is rejected, and the message.
std::pair<std::size_t, std::string> error_of(const std::string& text)
{
  try {
    Formula(text, symbols);
  } catch (const FormulaError& e) {
    return {e.position(), e.what()};
  }
  return {std::string::npos, ""};
}

TEST(Formula, PrecedenceIsTheUsualOne)
{
  EXPECT_DOUBLE_EQ(value_of("a + b*c"), 8.0);
  EXPECT_DOUBLE_EQ(value_of("(a + b)*c"), 10.0);
  EXPECT_DOUBLE_EQ(value_of("a - b - c"), -3.0); // left to right
  EXPECT_DOUBLE_EQ(value_of("a / b / c"), 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(value_of("a*b^c"), 18.0); // ^ binds tighter than *
  EXPECT_DOUBLE_EQ(value_of("b^c*a"), 18.0);
}

TEST(Formula, PowerIsRightAssociativeAndUnaryMinusBindsLooserThanIt)
{
  EXPECT_DOUBLE_EQ(value_of("a^b^c"), 512.0); // 2^(3^2), not (2^3)^2 = 64
  EXPECT_DOUBLE_EQ(value_of("-a^2"), -4.0);   // -(a^2)
  EXPECT_DOUBLE_EQ(value_of("(-a)^2"), 4.0);
  EXPECT_DOUBLE_EQ(value_of("a^-b"), 0.125); // a^(-b)
  EXPECT_DOUBLE_EQ(value_of("a*-b"), -6.0);
  EXPECT_DOUBLE_EQ(value_of("--a"), 2.0);
  EXPECT_DOUBLE_EQ(value_of("+a - -b"), 5.0);
  EXPECT_DOUBLE_EQ(value_of("-(x - y)^2"), -1.0);
}

TEST(Formula, NumbersAndFunctions)
{
  EXPECT_DOUBLE_EQ(value_of("2.5e-3*1e3"), 2.5);
  EXPECT_DOUBLE_EQ(value_of(".5 + 1."), 1.5);
  EXPECT_DOUBLE_EQ(value_of("exp(x)"), std::exp(0.5));
  EXPECT_DOUBLE_EQ(value_of("log(y)"), std::log(1.5));
  EXPECT_DOUBLE_EQ(value_of("sqrt(b)"), std::sqrt(3.0));
  EXPECT_DOUBLE_EQ(value_of("pow(a, b)"), 8.0);
  EXPECT_DOUBLE_EQ(value_of("y^0.5"), std::sqrt(1.5));
  EXPECT_DOUBLE_EQ(value_of("abs(x - y)"), 1.0);
  EXPECT_DOUBLE_EQ(value_of("min(a, b) + 10*max(a, b)"), 32.0);
  EXPECT_DOUBLE_EQ(value_of("step(x - 0.5) + 2*step(x - 0.6)"), 1.0); // step(0) = 1
}

TEST(Formula, RepeatedSubexpressionsAreStoredOnce)
{
  const Formula once("(x - 1)^2", symbols);
  const Formula twice("(x - 1)^2 + exp((x - 1)^2)", symbols);
  // x, 1, x-1, 2, ^ then exp and + only.
  EXPECT_EQ(once.nodes().size(), 5u);
  EXPECT_EQ(twice.nodes().size(), 7u);
  EXPECT_EQ(twice.first_use(3), 1u);
  EXPECT_FALSE(twice.uses(0));
}

TEST(Formula, EachMistakeIsOneErrorAtItsCharacter)
{
  EXPECT_EQ(error_of("a + q").first, 4u);
  EXPECT_NE(error_of("a + q").second.find("unknown symbol 'q'"), std::string::npos);
  EXPECT_EQ(error_of("a + * b").first, 4u);
  EXPECT_EQ(error_of("a b").first, 2u);
  EXPECT_EQ(error_of("3a").first, 1u);
  EXPECT_EQ(error_of("a**b").first, 2u);
  EXPECT_EQ(error_of("exp(a").first, 0u);
  EXPECT_NE(error_of("exp(a").second.find("')' missing"), std::string::npos);
  EXPECT_EQ(error_of("2*foo(a)").first, 2u);
  EXPECT_NE(error_of("2*foo(a)").second.find("unknown function 'foo'"), std::string::npos);
  EXPECT_EQ(error_of("exp(a, b)").first, 5u);
  EXPECT_EQ(error_of("pow(a)").first, 5u);
  EXPECT_EQ(error_of("a +").first, 3u);
  EXPECT_EQ(error_of("  ").first, 0u);
  EXPECT_EQ(error_of("(a + b))").first, 7u);
}

TEST(Formula, SecondOrderDerivativesAreExact)
{
  // f = a x^3 exp(b y) / (x + y), with a, b parameters and x, y the variables.
  const Formula f("a*x^3*exp(b*y)/(x + y)", symbols);
  const double a = 2.0, b = 0.3, x = 0.7, y = 1.9;
  using D = Dual2<double, 2>;
  const std::vector<D> values{D(a), D(b), D(0.0), D::variable(x, 0), D::variable(y, 1)};
  const D u = f.evaluate<D>(values);
  // By hand: g = a e^(by) x^3 / s, s = x + y.
  const double e = std::exp(b * y), s = x + y;
  const double g = a * e * x * x * x / s;
  const double gx = a * e * (3 * x * x / s - x * x * x / (s * s));
  const double gy = a * e * x * x * x * (b / s - 1 / (s * s));
  const double gxx = a * e * (6 * x / s - 6 * x * x / (s * s) + 2 * x * x * x / (s * s * s));
  const double gxy =
      a * e * (3 * x * x * (b / s - 1 / (s * s)) - x * x * x * (b / (s * s) - 2 / (s * s * s)));
  const double gyy = a * e * x * x * x * (b * b / s - 2 * b / (s * s) + 2 / (s * s * s));
  EXPECT_NEAR(u.v, g, 1e-14 * std::abs(g));
  EXPECT_NEAR(u.g[0], gx, 1e-14 * std::abs(gx));
  EXPECT_NEAR(u.g[1], gy, 1e-13 * std::abs(gy));
  EXPECT_NEAR(u.h[D::at(0, 0)], gxx, 1e-13 * std::abs(gxx));
  EXPECT_NEAR(u.h[D::at(0, 1)], gxy, 1e-13 * std::abs(gxy));
  EXPECT_NEAR(u.h[D::at(1, 1)], gyy, 1e-13 * std::abs(gyy));

  // The program with the parameters folded in gives the same numbers.
  std::vector<double> fixed(f.nodes().size(), std::nan(""));
  const std::vector<double> all{a, b, 0.0, NAN, NAN};
  std::vector<double> nodes;
  f.evaluate<double>(all, nodes);
  const std::vector<int> variables{3, 4};
  const auto varying = f.depends_on(variables);
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (!varying[i]) fixed[i] = nodes[i];
  const FormulaProgram program(f, fixed);
  std::vector<D> registers;
  const D w = program.run<2, 2>(values, registers);
  EXPECT_EQ(w.v, u.v);
  for (int k = 0; k < 2; ++k) EXPECT_NEAR(w.g[k], u.g[k], 1e-15 * std::abs(u.g[k]));
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(w.h[k], u.h[k], 1e-14 * std::abs(u.h[k]));
}

TEST(Formula, EveryOperationDifferentiatesLikeItsRule)
{
  // Each case: formula of x (= symbol 3), its first and second derivative at x = 0.5, with
  // parameters a = 2 (constant operands on either side: the program's mixed operations).
  struct Case {
    const char* text;
    double d1, d2;
  };
  const double x = 0.5;
  const std::vector<Case> cases{
      {"a + x", 1, 0},
      {"x - a", 1, 0},
      {"a - x", -1, 0},
      {"a*x^3", 6 * x * x, 12 * x},
      {"x^a", 2 * x, 2},
      {"a^x", std::log(2) * std::pow(2, x), std::log(2) * std::log(2) * std::pow(2, x)},
      {"x^x", std::pow(x, x) * (std::log(x) + 1),
       std::pow(x, x) * ((std::log(x) + 1) * (std::log(x) + 1) + 1 / x)},
      {"a/x", -2 / (x * x), 4 / (x * x * x)},
      {"x/a", 0.5, 0},
      {"x^-1.5", -1.5 * std::pow(x, -2.5), 3.75 * std::pow(x, -3.5)},
      {"sqrt(x)", 0.5 / std::sqrt(x), -0.25 * std::pow(x, -1.5)},
      {"log(x)", 1 / x, -1 / (x * x)},
      {"exp(a*x)", 2 * std::exp(2 * x), 4 * std::exp(2 * x)},
      {"abs(x - a)^3", -3 * 1.5 * 1.5, 6 * 1.5},
      {"max(x, a)*x", 2, 0},
      {"min(x, a)*x", 2 * x, 2},
      {"step(x - 0.25)*x^2", 2 * x, 2},
      {"-x^2", -2 * x, -2},
  };
  using D = Dual2<double, 1>;
  for (const Case& c : cases) {
    const Formula f(c.text, symbols);
    std::vector<double> fixed(f.nodes().size(), std::nan("")), nodes;
    const std::vector<double> all{2.0, 0.0, 0.0, NAN, 0.0};
    f.evaluate<double>(all, nodes);
    const std::vector<int> variables{3};
    const auto varying = f.depends_on(variables);
    for (std::size_t i = 0; i < nodes.size(); ++i)
      if (!varying[i]) fixed[i] = nodes[i];
    const std::vector<D> values{D(2.0), D(0.0), D(0.0), D::variable(x, 0), D(0.0)};
    std::vector<D> registers;
    const D u = FormulaProgram(f, fixed).run<1, 2>(values, registers);
    const D v = f.evaluate<D>(values);
    EXPECT_NEAR(u.g[0], c.d1, 1e-14 * (1 + std::abs(c.d1))) << c.text;
    EXPECT_NEAR(u.h[0], c.d2, 1e-13 * (1 + std::abs(c.d2))) << c.text;
    EXPECT_NEAR(v.g[0], c.d1, 1e-14 * (1 + std::abs(c.d1))) << c.text;
    EXPECT_NEAR(v.h[0], c.d2, 1e-13 * (1 + std::abs(c.d2))) << c.text;
  }
}

} // namespace
} // namespace ibvalve::materials
