// Biaxial stresses and fits of laws written as formulas (materials/expression_fitting.hpp): the
// analytic biaxial stresses equal the law's 3-D stress on the homogeneous deformation and the built-in
// laws' biaxial stresses; the W1 formula fitted to data gives the built-in W1 fit's parameters.
#include <cmath>
#include <iostream>
#include <vector>

#include <gtest/gtest.h>

#include "base/units.hpp"
#include "materials/expression_fitting.hpp"

namespace ibvalve::materials {
namespace {

constexpr double kPa = units::kPa;

TEST(ExpressionBiaxial, EqualsTheLawsThreeDimensionalStressForEveryInvariant)
{
  // Two families at +-35 deg; I1bar, I2, I4, I6, I8 and J all read.
  const std::vector<ExpressionParameter> p{{"c1", 3 * kPa, true}, {"c2", 1 * kPa, true},
                                           {"k", 20 * kPa, true}, {"b", 2.0, false},
                                           {"q", 5 * kPa, true},  {"kappa", 50 * kPa, true}};
  const double angle = 35.0 * M_PI / 180.0;
  FiberFrame frame;
  frame.f0 = Vec3(std::cos(angle), std::sin(angle), 0.0);
  frame.s0 = Vec3(std::cos(angle), -std::sin(angle), 0.0);
  std::vector<double> values;
  for (const auto& q : p) values.push_back(q.value);
  for (const auto fibers : {FiberCompression::excluded, FiberCompression::included}) {
    const ExpressionLaw law(
        "c1*(I1bar - 3) + c2*(I2 - 3)^2 + k*(I6 - 1)^2*exp(b*(I4 - 1)) + q*I8^2*(I4 - 1)^2 "
        "+ kappa*(J - 1)^2",
        p, {fibers});
    double worst = 0.0;
    for (const double l1 : {0.92, 1.0, 1.1, 1.2})
      for (const double l2 : {0.95, 1.05, 1.15}) {
        const auto a = expression_biaxial_cauchy(law, values, angle, l1, l2);
        const auto b = biaxial_cauchy_through_stress(law, frame, l1, l2);
        const double scale = std::max(std::abs(b[0]) + std::abs(b[1]), 1.0);
        worst = std::max({worst, std::abs(a[0] - b[0]) / scale, std::abs(a[1] - b[1]) / scale});
      }
    std::cout << "biaxial stresses, analytic against the 3-D stress: max relative difference " << worst
              << "\n";
    EXPECT_LT(worst, 1e-12);
  }
}

BiaxialSample w1_sample()
{
  const std::vector<double> w1{1.21, 7.99, 24.23, 57.62};
  BiaxialSample sample;
  sample.name = "w1";
  const double ends[][2] = {{1.10, 1.25}, {1.10, 1.15}, {1.10, 1.05}, {1.06, 1.25}, {1.03, 1.25}};
  for (const auto& end : ends)
    for (int k = 1; k <= 15; ++k) {
      const double t = k / 15.0;
      BiaxialPoint pt{1.0 + t * (end[0] - 1.0), 1.0 + t * (end[1] - 1.0), 0.0, 0.0};
      const auto s = biaxial_cauchy<double>({LawKind::W1}, w1.data(), pt.lambda1, pt.lambda2);
      pt.sigma11 = s[0] * (1.0 + 0.02 * std::sin(7.0 * k)) + 0.3 * std::cos(3.0 * k); // a fixed "noise"
      pt.sigma22 = s[1] * (1.0 + 0.02 * std::cos(5.0 * k)) + 0.3 * std::sin(2.0 * k);
      sample.points.push_back(pt);
    }
  return sample;
}

TEST(ExpressionFit, TheW1FormulaFitsLikeTheBuiltInW1)
{
  const BiaxialSample sample = w1_sample();
  const FitResult built_in = fit_biaxial(sample, FitOptions{});
  ExpressionFitOptions options;
  options.energy = "C10*(exp(C01*(I1 - 3)) - 1) + k1/(2*k2)*(exp(k2*(I4 - 1)^2) - 1)";
  options.parameters = {
      {"C10", 2.0, true, 0.0}, {"C01", 5.0, false, 0.0}, {"k1", 10.0, true, 0.0}, {"k2", 30.0, false, 0.0}};
  const FitResult fit = fit_expression(sample, options);
  // The built-in fit's order: C10, C01, k1, k2.
  double worst = 0.0;
  for (std::size_t i = 0; i < 4; ++i)
    worst = std::max(worst, std::abs(fit.parameters[i] - built_in.parameters[i]) / built_in.parameters[i]);
  std::cout << "W1 formula against built-in W1 on the same data: max relative parameter difference " << worst
            << ", R^2 " << fit.quality.r_squared << " and " << built_in.quality.r_squared << "\n";
  EXPECT_TRUE(fit.converged);
  EXPECT_LT(worst, 1e-6);
  EXPECT_NEAR(fit.quality.sse, built_in.quality.sse, 1e-9 * built_in.quality.sse);
}

TEST(ExpressionFit, EveryBuiltInLawWrittenAsAFormulaFitsLikeItsBuiltInSelf)
{
  // Data of each law (with a fixed perturbation), fitted by the built-in fit and by its formula started
  // 20 % away from the built-in optimum; both reach the same parameters.
  struct Case {
    const char* label;
    BiaxialSetup setup;
    std::vector<double> truth; // kPa for moduli
    std::string energy;
    std::vector<FittedParameter> parameters; // name, (start), modulus, lower, upper
    FiberCompression fibers;
  };
  const double hgo_angle = 30.0 * M_PI / 180.0;
  const std::string family = "k1/(2*k2)*(exp(k2*(kappa*(I1 - 3) + (1 - 3*kappa)*(I@ - 1))^2) - 1)";
  auto hgo_family = [&](const char* i) { return std::string(family).replace(family.find('@'), 1, i); };
  const std::vector<Case> cases{
      {"neo-Hookean",
       {LawKind::neo_hookean},
       {50.0},
       "mu/2*(I1 - 3)",
       {{"mu", 0, true, 0.0}},
       FiberCompression::excluded},
      {"W2",
       {LawKind::W2},
       {1.18, 55.04, 8.08, 54.0},
       "mu*(I1 - 3) + c0*(exp(c1*(I1 - 3)^2 + c2*(I4 - 1)^4) - 1)",
       {{"mu", 0, true, 0.0}, {"c0", 0, true, 0.0}, {"c1", 0, false, 0.0}, {"c2", 0, false, 0.0}},
       FiberCompression::excluded},
      {"W3",
       {LawKind::W3},
       {19.59, 12.94, 77.79},
       "C1*(I1 - 3) + a/(2*b)*(exp(b*(I4 - 1)^2) - 1)",
       {{"C1", 0, true, 0.0}, {"a", 0, true, 0.0}, {"b", 0, false, 0.0}},
       FiberCompression::excluded},
      {"hgo",
       {LawKind::hgo, FiberCompression::excluded, hgo_angle},
       {7.64, 99.66, 52.46, 0.226},
       "mu/2*(I1 - 3) + step(I4 - 1)*" + hgo_family("4") + " + step(I6 - 1)*" + hgo_family("6"),
       {{"mu", 0, true, 0.0},
        {"k1", 0, true, 0.0},
        {"k2", 0, false, 0.0},
        {"kappa", 0, false, 0.0, 1.0 / 3.0}},
       FiberCompression::included},
  };
  for (const Case& c : cases) {
    BiaxialSample sample;
    sample.name = c.label;
    for (int k = 1; k <= 60; ++k) {
      const double l1 = 1.0 + 0.12 * std::fmod(0.37 * k, 1.0), l2 = 1.0 + 0.2 * std::fmod(0.61 * k, 1.0);
      const auto s = biaxial_cauchy<double>(c.setup, c.truth.data(), l1, l2);
      sample.points.push_back({l1, l2, s[0] * (1.0 + 0.02 * std::sin(7.0 * k)) + 0.2 * std::cos(3.0 * k),
                               s[1] * (1.0 + 0.02 * std::cos(5.0 * k)) + 0.2 * std::sin(2.0 * k)});
    }
    FitOptions built_in_options;
    built_in_options.setup = c.setup;
    const FitResult built_in = fit_biaxial(sample, built_in_options);
    ExpressionFitOptions options;
    options.energy = c.energy;
    options.parameters = c.parameters;
    options.fiber_compression = c.fibers;
    options.fiber_angle = c.setup.fiber_angle;
    for (std::size_t i = 0; i < options.parameters.size(); ++i)
      options.parameters[i].start = std::min(built_in.parameters[i] * 1.2, options.parameters[i].upper);
    const FitResult fit = fit_expression(sample, options);
    double worst = 0.0;
    for (std::size_t i = 0; i < fit.parameters.size(); ++i)
      worst = std::max(worst, std::abs(fit.parameters[i] - built_in.parameters[i]) /
                                  std::max(std::abs(built_in.parameters[i]), 1e-12));
    std::cout << c.label << " formula against built-in fit: max relative parameter difference " << worst
              << ", SSE " << fit.quality.sse << " and " << built_in.quality.sse << "\n";
    EXPECT_LT(worst, 1e-6) << c.label;
    EXPECT_NEAR(fit.quality.sse, built_in.quality.sse, 1e-8 * built_in.quality.sse) << c.label;
  }
}

TEST(ExpressionFit, BoundsHoldAndAStartOutsideThemIsAnInputError)
{
  const BiaxialSample sample = w1_sample();
  ExpressionFitOptions options;
  options.energy = "C10*(exp(C01*(I1 - 3)) - 1) + k1/(2*k2)*(exp(k2*(I4 - 1)^2) - 1)";
  options.parameters = {{"C10", 2.0, true, 0.0},
                        {"C01", 5.0, false, 0.0},
                        {"k1", 10.0, true, 0.0},
                        {"k2", 30.0, false, 0.0, 40.0}};
  const FitResult fit = fit_expression(sample, options);
  EXPECT_LE(fit.parameters[3], 40.0);
  EXPECT_NEAR(fit.parameters[3], 40.0, 1e-9); // the optimum (57.6) lies beyond: the bound is active
  options.parameters[3].start = 50.0;
  EXPECT_THROW(fit_expression(sample, options), std::exception);
}

} // namespace
} // namespace ibvalve::materials
