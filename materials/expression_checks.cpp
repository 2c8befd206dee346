#include "materials/expression_checks.hpp"

#include <cmath>
#include <fmt/format.h>

#include "materials/formula_ad.hpp"

namespace ibvalve::materials {

namespace {

/// A stretch path of the biaxial test, F = diag(l1(t), l2(t), 1/(l1 l2)), t from 0.8 to 1.3.
struct StretchPath {
  const char* name;
  bool stretch1, stretch2; ///< which in-plane stretches are t (the others stay 1)
};

constexpr StretchPath paths[] = {{"equibiaxial stretch", true, true},
                                 {"strip stretch along the fibers (I4)", true, false},
                                 {"strip stretch across the fibers", false, true}};

/// The fiber frame the checks use: f0 along axis 1, s0 along axis 2.
FiberFrame check_frame()
{
  FiberFrame frame;
  frame.f0 = Vec3::UnitX();
  frame.s0 = Vec3::UnitY();
  return frame;
}

Mat3 path_F(const StretchPath& path, double t)
{
  const double l1 = path.stretch1 ? t : 1.0, l2 = path.stretch2 ? t : 1.0;
  return Vec3(l1, l2, 1.0 / (l1 * l2)).asDiagonal();
}

bool finite(const ExpressionResponse& r)
{
  if (!std::isfinite(r.psi)) return false;
  for (int k = 0; k < kinematic_count; ++k) {
    if (!std::isfinite(r.d[k])) return false;
    for (int l = 0; l < kinematic_count; ++l)
      if (!std::isfinite(r.dd[k][l])) return false;
  }
  return true;
}

/// Where in the formula the first value or derivative that is not finite arises at the invariants `x`:
/// the formula evaluated node by node with each of its invariant symbols an independent variable.
std::size_t locate_non_finite(const ExpressionLaw& law, const std::array<double, kinematic_count>& raw)
{
  constexpr int n = static_cast<int>(expression_invariants.size());
  using Number = Dual2<double, n>;
  std::array<double, kinematic_count> x = raw;
  if (law.options().fiber_compression == FiberCompression::excluded) {
    x[kI4] = std::max(x[kI4], 1.0);
    x[kI6] = std::max(x[kI6], 1.0);
  }
  const double I1bar = x[kI1] * std::pow(x[kJ], -2.0 / 3.0);
  const bool isochoric = law.options().isotropic_invariant == IsotropicInvariant::isochoric;
  const std::array<double, n> invariants{
      isochoric ? I1bar : x[kI1], I1bar, x[kI2], x[kI4], x[kI6], x[kI8], x[kJ]};
  std::vector<Number> symbols;
  for (int i = 0; i < n; ++i) symbols.push_back(Number::variable(invariants[static_cast<std::size_t>(i)], i));
  for (const auto& p : law.parameters()) symbols.push_back(Number(p.value));
  std::vector<Number> nodes;
  law.formula().evaluate<Number>(symbols, nodes);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    bool ok = std::isfinite(nodes[i].v);
    for (const double g : nodes[i].g) ok = ok && std::isfinite(g);
    for (const double h : nodes[i].h) ok = ok && std::isfinite(h);
    if (!ok) return law.formula().nodes()[i].position;
  }
  return std::string::npos;
}

std::string moduli_names(const ExpressionLaw& law)
{
  std::string names;
  for (const auto& p : law.parameters())
    if (p.is_modulus) names += (names.empty() ? "" : ", ") + p.name;
  return names.empty() ? "none" : names;
}

std::optional<ExpressionProblem> check_units(const ExpressionLaw& law)
{
  std::vector<double> values, doubled;
  for (const auto& p : law.parameters()) {
    values.push_back(p.value);
    doubled.push_back(p.is_modulus ? 2.0 * p.value : p.value);
  }
  const FiberFrame frame = check_frame();
  for (const Mat3& F : {path_F(paths[0], 1.2), path_F(paths[1], 1.15), path_F(paths[2], 0.9)}) {
    const auto x = ExpressionLaw::invariants_of(F, frame);
    const double W = law.energy_with(values, x), W2 = law.energy_with(doubled, x);
    if (std::isfinite(W) && std::isfinite(W2) &&
        std::abs(W2 - 2.0 * W) > 1e-9 * std::max(std::abs(W2), 1e-300))
      return ExpressionProblem{"the energy is not a stress in the moduli (" + moduli_names(law) +
                               "): doubling them does not double it. List in `moduli` every parameter "
                               "given in kPa, and only those (the others are dimensionless)"};
  }
  return std::nullopt;
}

} // namespace

std::optional<ExpressionProblem> check_expression_law(const ExpressionLaw& law)
{
  if (auto problem = check_units(law)) return problem;
  const FiberFrame frame = check_frame();
  std::vector<Mat3> points{Mat3::Identity()};
  for (const auto& path : paths)
    for (const double t : {0.8, 0.9, 1.1, 1.2, 1.3}) points.push_back(path_F(path, t));
  for (const Mat3& F : points) {
    const auto x = ExpressionLaw::invariants_of(F, frame);
    if (!finite(law.response(x)))
      return ExpressionProblem{
          fmt::format("the energy or its derivatives are not finite at I1 = {:.4g}, I4 = {:.4g}, J = 1 "
                      "(F = diag({:.4g}, {:.4g}, {:.4g}))",
                      x[kI1], x[kI4], F(0, 0), F(1, 1), F(2, 2)),
          locate_non_finite(law, x)};
  }
  // The stress at F = I: the fiber terms must vanish there (the hydrostatic part is the reference
  // term's). Scale: the largest modulus, or the isotropic derivatives.
  const ExpressionResponse r = law.response({3.0, 3.0, 1.0, 1.0, 0.0, 1.0});
  double scale = std::abs(r.d[kI1]) + std::abs(r.d[kI2]) + std::abs(r.d[kJ]);
  for (const auto& p : law.parameters())
    if (p.is_modulus) scale = std::max(scale, std::abs(p.value));
  const std::array<std::pair<int, const char*>, 3> fibers{{{kI4, "I4"}, {kI6, "I6"}, {kI8, "I8"}}};
  const std::array<int, 3> symbol{3, 4, 5}; // I4, I6, I8 in expression_invariants
  for (std::size_t i = 0; i < fibers.size(); ++i) {
    const double d = r.d[static_cast<std::size_t>(fibers[i].first)];
    if (std::abs(d) > 1e-12 * scale)
      return ExpressionProblem{
          fmt::format("the stress at F = I is not zero: dW/d{} = {:.6g} kPa there (I4 = I6 "
                      "= 1, I8 = 0); a fiber term must vanish with its slope at the "
                      "reference, e.g. ({} - 1)^2",
                      fibers[i].second, d / 1e4, fibers[i].second),
          law.formula().first_use(symbol[i])};
  }
  return std::nullopt;
}

std::vector<std::string> convexity_warnings(const ExpressionLaw& law)
{
  std::vector<std::string> warnings;
  const FiberFrame frame = check_frame();
  for (const auto& path : paths) {
    // d2W/dt2 = dF:T:dF + P:d2F along F(t) = diag(l1, l2, l3), l3 = 1/(l1 l2).
    std::vector<std::pair<double, double>> curvature;
    double largest = 0.0;
    for (int k = 0; k <= 50; ++k) {
      const double t = 0.8 + 0.5 * k / 50.0;
      const Mat3 F = path_F(path, t);
      const double n = (path.stretch1 ? 1.0 : 0.0) + (path.stretch2 ? 1.0 : 0.0); // l3 = t^-n
      Eigen::Matrix<double, 9, 1> dF = Eigen::Matrix<double, 9, 1>::Zero(), d2F = dF;
      dF(0) = path.stretch1 ? 1.0 : 0.0;
      dF(4) = path.stretch2 ? 1.0 : 0.0;
      dF(8) = -n * std::pow(t, -n - 1.0);
      d2F(8) = n * (n + 1.0) * std::pow(t, -n - 2.0);
      Mat3 P;
      Tangent T;
      law.stress_and_tangent(F, frame, P, T);
      const double c = dF.dot(T * dF) + Eigen::Map<const Eigen::Matrix<double, 9, 1>>(P.data()).dot(d2F);
      curvature.emplace_back(t, c);
      largest = std::max(largest, std::abs(c));
    }
    for (const auto& [t, c] : curvature)
      if (c < -1e-9 * largest) {
        warnings.push_back(fmt::format("the energy is not convex along the {} at stretch {:.3g} "
                                       "(d2W/dt2 = {:.4g} kPa): the fit and the finite elements may find "
                                       "more than one state there",
                                       path.name, t, c / 1e4));
        break;
      }
  }
  return warnings;
}

} // namespace ibvalve::materials
