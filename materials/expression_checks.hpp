#pragma once
// The checks an expression law passes before it is used (docs/materials.md, "Laws written as
// formulas"): each failure is one message with, where it has one, the character of the formula it
// points at.
//  - units: the energy is a stress, so it must be homogeneous of degree 1 in the moduli (the parameters
//    given in kPa) and of degree 0 in the others (dimensionless): doubling every modulus doubles W
//    (Buckingham: W / mu = f(invariants, the other parameters)). This catches a modulus left out of
//    `moduli` or a dimensionless parameter put in it;
//  - finiteness: W and its first and second derivatives are finite at F = I and along the uniaxial
//    and equibiaxial stretches of a biaxial test (stretch 0.8 to 1.3);
//  - the stress-free reference: at F = I the fiber derivatives dW/dI4, dW/dI6, dW/dI8 vanish (the
//    hydrostatic part is what the reference term removes, law.hpp).
// And one warning, not an error: where W loses convexity along those stretch paths (d2W/dt2 < 0 along
// F(t)), which the fit's data cover and where a finite element solution loses uniqueness.
#include <optional>
#include <string>
#include <vector>

#include "materials/expression_law.hpp"

namespace ibvalve::materials {

struct ExpressionProblem {
  std::string message;
  std::size_t position = std::string::npos; ///< in the formula, or npos when the problem has no place
};

/// The first failed check, or nothing when the law passes them all.
std::optional<ExpressionProblem> check_expression_law(const ExpressionLaw& law);

/// One line per stretch path along which W is not convex (the first stretch where it fails).
std::vector<std::string> convexity_warnings(const ExpressionLaw& law);

} // namespace ibvalve::materials
