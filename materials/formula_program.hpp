#pragma once
// A formula specialised for its parameters' values, for fast evaluation with derivatives: every part
// of the formula that reads no variable (the parameters, the numbers) is computed once, and the
// operations left take such parts as plain numbers (a product by a constant scales a Dual2 instead of
// applying the full product rule). What the finite elements call at every quadrature point.
#include <cmath>
#include <span>
#include <vector>

#include "materials/formula.hpp"
#include "materials/formula_ad.hpp"

namespace ibvalve::materials {

class FormulaProgram {
 public:
  FormulaProgram() = default;
  /// `fixed` holds one value per node of `formula`: the node's value when it reads no variable, NaN
  /// otherwise. Symbols read by nodes that are not fixed are the variables, taken from `run`'s inputs.
  FormulaProgram(const Formula& formula, std::span<const double> fixed);

  /// The formula's value with its derivatives; `inputs[s]` is the value of symbol s (used for the
  /// variables only); `registers` is a buffer (resized as needed).
  template <int N, int Order = 2>
  Dual2<double, N, Order> run(std::span<const Dual2<double, N, Order>> inputs,
                              std::vector<Dual2<double, N, Order>>& registers) const;

 private:
  struct Operand {
    int node = -1;      ///< a register (a node that reads a variable), or -1 for the constant
    double value = 0.0; ///< the constant
  };
  struct Instruction {
    FormulaOp op = FormulaOp::constant;
    int target = -1;
    int symbol = -1; ///< FormulaOp::symbol: the input to load
    Operand a, b;
  };
  std::vector<Instruction> code_;
  std::size_t nodes_ = 0;
  double result_ = 0.0; ///< the value when the whole formula is fixed (no instruction)
};

namespace formula_program_detail {

template <int N, int O>
Dual2<double, N, O> scaled(Dual2<double, N, O> x, double c)
{
  x.v *= c;
  for (auto& gi : x.g) gi *= c;
  for (auto& hk : x.h) hk *= c;
  return x;
}

/// A binary operation with at least one operand that carries derivatives.
template <int N, int O>
Dual2<double, N, O> binary(FormulaOp op, const Dual2<double, N, O>* a, double ca,
                           const Dual2<double, N, O>* b, double cb)
{
  using Number = Dual2<double, N, O>;
  switch (op) {
  case FormulaOp::add:
    if (!a) return Number(ca) + *b; // (constants as Dual2: additions are cheap either way)
    if (!b) return *a + Number(cb);
    return *a + *b;
  case FormulaOp::subtract:
    if (!a) return Number(ca) - *b;
    if (!b) return *a - Number(cb);
    return *a - *b;
  case FormulaOp::multiply:
    if (!a) return scaled(*b, ca);
    if (!b) return scaled(*a, cb);
    return *a * *b;
  case FormulaOp::divide:
    if (!b) return scaled(*a, 1.0 / cb);
    if (!a) {
      const double r = 1.0 / b->v; // c/b: f' = -c/b^2, f'' = 2c/b^3
      return chain(*b, ca * r, -ca * r * r, 2.0 * ca * r * r * r);
    }
    return *a / *b;
  case FormulaOp::power:
    if (!b) return formula_power(*a, cb);
    if (!a) { // c^b = e^(b ln c)
      const double lc = std::log(ca), e = std::exp(b->v * lc);
      return chain(*b, e, lc * e, lc * lc * e);
    }
    return exp(*b * log(*a));
  case FormulaOp::min:
    if (!a) return *b < Number(ca) ? *b : Number(ca);
    if (!b) return Number(cb) < *a ? Number(cb) : *a;
    return *b < *a ? *b : *a;
  case FormulaOp::max:
    if (!a) return *b < Number(ca) ? Number(ca) : *b;
    if (!b) return *a < Number(cb) ? Number(cb) : *a;
    return *a < *b ? *b : *a;
  default:
    return Number(std::nan(""));
  }
}

} // namespace formula_program_detail

template <int N, int Order>
Dual2<double, N, Order> FormulaProgram::run(std::span<const Dual2<double, N, Order>> inputs,
                                            std::vector<Dual2<double, N, Order>>& r) const
{
  using Number = Dual2<double, N, Order>;
  if (code_.empty()) return Number(result_);
  r.resize(nodes_);
  for (const Instruction& in : code_) {
    const Number* a = in.a.node >= 0 ? &r[static_cast<std::size_t>(in.a.node)] : nullptr;
    const Number* b = in.b.node >= 0 ? &r[static_cast<std::size_t>(in.b.node)] : nullptr;
    Number& t = r[static_cast<std::size_t>(in.target)];
    switch (in.op) {
    case FormulaOp::symbol:
      t = inputs[static_cast<std::size_t>(in.symbol)];
      break;
    case FormulaOp::negate:
      t = -*a;
      break;
    case FormulaOp::exp:
      t = exp(*a);
      break;
    case FormulaOp::log:
      t = log(*a);
      break;
    case FormulaOp::sqrt:
      t = sqrt(*a);
      break;
    case FormulaOp::abs:
      t = a->v < 0.0 ? -*a : *a;
      break;
    case FormulaOp::step:
      t = Number(a->v < 0.0 ? 0.0 : 1.0);
      break;
    default:
      t = formula_program_detail::binary<N, Order>(in.op, a, in.a.value, b, in.b.value);
    }
  }
  return r[static_cast<std::size_t>(code_.back().target)];
}

} // namespace ibvalve::materials
