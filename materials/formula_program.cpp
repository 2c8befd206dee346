#include "materials/formula_program.hpp"

namespace ibvalve::materials {

FormulaProgram::FormulaProgram(const Formula& formula, std::span<const double> fixed)
    : nodes_(formula.nodes().size())
{
  const auto nodes = formula.nodes();
  auto operand = [&](int node) {
    if (node < 0) return Operand{};
    const double value = fixed[static_cast<std::size_t>(node)];
    return std::isnan(value) ? Operand{node, 0.0} : Operand{-1, value};
  };
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (!std::isnan(fixed[i])) continue;
    const FormulaNode& n = nodes[i];
    code_.push_back({n.op, static_cast<int>(i), n.symbol, operand(n.a), operand(n.b)});
  }
  if (code_.empty()) result_ = fixed.back();
}

} // namespace ibvalve::materials
