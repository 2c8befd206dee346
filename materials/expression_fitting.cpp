#include "materials/expression_fitting.hpp"

#include <cmath>
#include <fmt/format.h>

#include <ceres/ceres.h>

#include "materials/ceres_fit_options.hpp"

#include "base/errors.hpp"
#include "materials/formula_ad.hpp"

namespace ibvalve::materials {

namespace {

/// (sigma11, sigma22) of the formula with parameters `p` (any scalar: double, or Ceres Jets for the
/// fit's derivatives in the parameters); see expression_fitting.hpp for the stress.
template <class T>
std::array<T, 2> biaxial(const Formula& formula, const T* p, std::size_t count, FiberCompression fibers,
                         double angle, double l1, double l2)
{
  using Number = Dual2<T, 5, 1>; // first derivatives in I1, I2, I4, I6, I8
  const double l3 = 1.0 / (l1 * l2);
  const double c = std::cos(angle), s = std::sin(angle);
  const double b1 = l1 * l1, b2 = l2 * l2, b3 = l3 * l3;
  const double I1 = b1 + b2 + b3, I2 = b1 * b2 + b2 * b3 + b3 * b1;
  const double I4 = b1 * c * c + b2 * s * s, I8 = b1 * c * c - b2 * s * s; // I6 = I4
  const bool slack = fibers == FiberCompression::excluded && I4 < 1.0;
  const Number fiber = slack ? Number(1.0) : Number::variable(T(I4), 2);
  const Number fiber6 = slack ? Number(1.0) : Number::variable(T(I4), 3);
  std::vector<Number> symbols{Number::variable(T(I1), 0),
                              Number::variable(T(I1), 0),
                              Number::variable(T(I2), 1),
                              fiber,
                              fiber6,
                              Number::variable(T(I8), 4),
                              Number(1.0)};
  for (std::size_t i = 0; i < count; ++i) symbols.push_back(Number(p[i]));
  const Number W = formula.evaluate<Number>(symbols);
  const T &d1 = W.g[0], &d2 = W.g[1], &d4 = W.g[2], &d6 = W.g[3], &d8 = W.g[4];
  const T A = T(2.0) * (d1 + T(I1) * d2);
  auto isotropic = [&](double b) { return A * T(b) - T(2.0 * b * b) * d2; };
  const T fibers1 = T(2.0 * b1 * c * c) * (d4 + d6 + d8), fibers2 = T(2.0 * b2 * s * s) * (d4 + d6 - d8);
  return {isotropic(b1) - isotropic(b3) + fibers1, isotropic(b2) - isotropic(b3) + fibers2};
}

struct ExpressionResidual {
  const Formula* formula;
  std::size_t count;
  FiberCompression fibers;
  double angle;
  BiaxialPoint point;

  template <class T>
  bool operator()(T const* const* p, T* r) const
  {
    const auto s = biaxial<T>(*formula, p[0], count, fibers, angle, point.lambda1, point.lambda2);
    r[0] = s[0] - T(point.sigma11);
    r[1] = s[1] - T(point.sigma22);
    using std::isfinite;
    return isfinite(r[0]) && isfinite(r[1]); // a trial step that overflows is rejected
  }
};

/// The law of the formula with the starting values (parsing it; the values in user units).
ExpressionLaw law_of(const ExpressionFitOptions& options)
{
  std::vector<ExpressionParameter> parameters;
  for (const auto& p : options.parameters) parameters.push_back({p.name, p.start, p.is_modulus});
  try {
    return ExpressionLaw(options.energy, parameters, {options.fiber_compression});
  } catch (const FormulaError& e) {
    throw InputError(fmt::format("command line: --energy: character {}: {}", e.position() + 1, e.what()));
  }
}

} // namespace

std::array<double, 2> expression_biaxial_cauchy(const ExpressionLaw& law, std::span<const double> values,
                                                double fiber_angle, double lambda1, double lambda2)
{
  return biaxial<double>(law.formula(), values.data(), values.size(), law.options().fiber_compression,
                         fiber_angle, lambda1, lambda2);
}

FitResult fit_expression(const BiaxialSample& sample, const ExpressionFitOptions& options)
{
  const ExpressionLaw law = law_of(options);
  std::vector<double> p;
  for (const auto& q : options.parameters) {
    if (!(q.start >= q.lower && q.start <= q.upper))
      throw InputError(fmt::format("command line: --parameters: {} = {} lies outside its bounds [{}, {}]",
                                   q.name, q.start, q.lower, q.upper));
    p.push_back(q.start);
  }
  if (2 * sample.points.size() < p.size())
    throw InputError(fmt::format("{}: too few data points for {} parameters", sample.name, p.size()));
  ceres::Problem problem;
  for (const auto& pt : sample.points) {
    auto* cost = new ceres::DynamicAutoDiffCostFunction<ExpressionResidual, 4>(
        new ExpressionResidual{&law.formula(), p.size(), options.fiber_compression, options.fiber_angle, pt});
    cost->AddParameterBlock(static_cast<int>(p.size()));
    cost->SetNumResiduals(2);
    problem.AddResidualBlock(cost, nullptr, p.data());
  }
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto& q = options.parameters[i];
    if (std::isfinite(q.lower)) problem.SetParameterLowerBound(p.data(), static_cast<int>(i), q.lower);
    if (std::isfinite(q.upper)) problem.SetParameterUpperBound(p.data(), static_cast<int>(i), q.upper);
  }
  const ceres::Solver::Options solver = fit_solver_options(options.max_iterations);
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);
  FitResult result;
  result.parameters = p;
  result.solves = 1;
  result.converged = summary.termination_type == ceres::CONVERGENCE;
  const ExpressionLaw fitted = law_of(options);
  const double angle = options.fiber_angle;
  result.quality = fit_quality(sample, [&](const BiaxialPoint& pt) {
    return biaxial<double>(fitted.formula(), p.data(), p.size(), options.fiber_compression, angle, pt.lambda1,
                           pt.lambda2);
  });
  return result;
}

} // namespace ibvalve::materials
