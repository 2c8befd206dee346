#pragma once
// Planar biaxial stresses and least-squares fits of a law written as a formula (expression_law.hpp),
// as fitting.hpp does for the built-in laws.
//
// Biaxial stresses. On F = diag(l1, l2, l3), l3 = 1/(l1 l2) (J = 1), with d_k = dW/dI_k, the
// Cauchy stress is sigma = -p I + 2 (d1 + I1 d2) B - 2 d2 B^2 + 2 d4 f (x) f + 2 d6 s (x) s
// + d8 (f (x) s + s (x) f), B = diag(l^2), f = F f0, s = F s0 (Holzapfel 2000, eq. 6.32 with the
// invariants' derivatives), and sigma33 = 0 fixes p. The families lie at +-theta from axis 1
// (f0 = (cos, sin, 0), s0 = (cos, -sin, 0)), so the shear stresses cancel. J and I1bar's J-part only
// shift p: I1bar = I1 there. With one family (a formula without I6, I8) s0 is unused.
//
// Fit: minimise the squared stress misfit over the parameters from the user's starting values, each
// within its bounds (moduli >= 0 unless given), with Ceres' bounded Levenberg-Marquardt and automatic
// derivatives in the parameters through the same formula (one solve; the start is the user's).
#include <array>
#include <limits>
#include <string>
#include <vector>

#include "materials/expression_law.hpp"
#include "materials/fitting.hpp"

namespace ibvalve::materials {

/// A parameter to fit: its start (user units: kPa for a modulus) and bounds.
struct FittedParameter {
  std::string name;
  double start = 0.0;
  bool is_modulus = false;
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
};

struct ExpressionFitOptions {
  std::string energy;
  std::vector<FittedParameter> parameters;
  FiberCompression fiber_compression = FiberCompression::excluded;
  double fiber_angle = 0.0; ///< radians, of the families from axis 1
  int max_iterations = 1000;
};

/// (sigma11, sigma22) in the unit of the moduli in `values` (the parameters in the law's order).
std::array<double, 2> expression_biaxial_cauchy(const ExpressionLaw& law, std::span<const double> values,
                                                double fiber_angle, double lambda1, double lambda2);

/// The fitted parameters (user units) and the fit's quality. Throws InputError for a formula that
/// does not parse (the message names the character) or a start outside its bounds.
FitResult fit_expression(const BiaxialSample& sample, const ExpressionFitOptions& options);

} // namespace ibvalve::materials
