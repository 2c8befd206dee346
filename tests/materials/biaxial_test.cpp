// Planar biaxial analytics (materials/biaxial.hpp) against (a) the law's 3-D stress P evaluated on the
// homogeneous deformation F = diag(l1, l2, 1/(l1 l2)) of one element with sigma33 = 0 imposed, and
// (b) the Cauchy stresses written out in docs/reference.md, "Constitutive laws", for W1, W2, W3.
#include <cmath>
#include <iostream>
#include <memory>

#include <gtest/gtest.h>

#include "base/units.hpp"
#include "materials/biaxial.hpp"
#include "materials/material.hpp"

namespace ibvalve::materials {
namespace {

constexpr double kPa = units::kPa;

struct BiaxialCase {
  const char* label;
  BiaxialSetup setup;
  std::vector<double> parameters_cgs;
};

std::vector<BiaxialCase> cases()
{
  std::vector<BiaxialCase> out;
  for (const auto fc : {FiberCompression::excluded, FiberCompression::included}) {
    out.push_back({"neo-Hookean", {LawKind::neo_hookean, fc, 0.0}, {50 * kPa}});
    out.push_back({"W1", {LawKind::W1, fc, 0.0}, {1.21 * kPa, 7.99, 24.23 * kPa, 57.62}});
    out.push_back({"W2", {LawKind::W2, fc, 0.0}, {1.18 * kPa, 55.04 * kPa, 8.08, 54.0}});
    out.push_back({"W3", {LawKind::W3, fc, 0.0}, {19.59 * kPa, 12.94 * kPa, 77.79}});
    out.push_back(
        {"HGO at +-40 deg", {LawKind::hgo, fc, 40.0 * M_PI / 180.0}, {5 * kPa, 20 * kPa, 10.0, 0.1}});
  }
  return out;
}

TEST(Biaxial, AnalyticStressesEqualTheLawsStressOnAHomogeneousElement)
{
  double worst = 0.0;
  for (const auto& c : cases()) {
    // The full Material (pressure-like reference term and a stiff penalty): both only shift p.
    auto law = std::make_shared<InvariantLaw>(
        c.setup.law, c.parameters_cgs, LawOptions{c.setup.fiber_compression, ReferenceState::pressure_like});
    const Material material(law, VolumetricPenalty(PenaltyKind::quadratic_log, 1e4 * kPa));
    const FiberFrame frame = biaxial_frame(c.setup);
    for (double l1 = 0.90; l1 <= 1.2501; l1 += 0.05)
      for (double l2 = 0.90; l2 <= 1.2501; l2 += 0.05) {
        if (std::abs(l1 - 1.0) < 1e-9 && std::abs(l2 - 1.0) < 1e-9) continue;
        if (c.setup.fiber_compression == FiberCompression::excluded) {
          // stay off the fiber switch I4 = 1, where the two evaluations may pick different sides
          const double I4 = l1 * l1 * std::pow(std::cos(c.setup.fiber_angle), 2) +
                            l2 * l2 * std::pow(std::sin(c.setup.fiber_angle), 2);
          if (std::abs(I4 - 1.0) < 1e-9) continue;
        }
        const auto analytic = biaxial_cauchy<double>(c.setup, c.parameters_cgs.data(), l1, l2);
        const auto direct = biaxial_cauchy_through_stress(material, frame, l1, l2);
        const double error =
            std::hypot(analytic[0] - direct[0], analytic[1] - direct[1]) / std::hypot(direct[0], direct[1]);
        worst = std::max(worst, error);
        EXPECT_LT(error, 1e-8) << c.label << " at " << l1 << ", " << l2;
      }
  }
  std::cout << "max relative difference analytic vs 3-D stress (all laws, 8x8 stretches) = " << worst << "\n";
}

TEST(Biaxial, MatchesTheCauchyStressesOfTheReference)
{
  // docs/reference.md, "Constitutive laws": sigma_W1 = -p I + 2 C10 C01 e^{C01 (I1-3)} B
  // + 2 k1 (I4-1) e^{k2 (I4-1)^2} f (x) f, etc., with p from sigma33 = 0.
  const double l1 = 1.08, l2 = 1.17, l3 = 1 / (l1 * l2);
  const double I1 = l1 * l1 + l2 * l2 + l3 * l3, I4 = l1 * l1;
  const double C10 = 1.21, C01 = 7.99, k1 = 24.23, k2 = 57.62;
  const double iso1 = 2 * C10 * C01 * std::exp(C01 * (I1 - 3));
  const double fib1 = 2 * k1 * (I4 - 1) * std::exp(k2 * (I4 - 1) * (I4 - 1));
  const double w1[] = {C10, C01, k1, k2};
  auto s = biaxial_cauchy<double>({LawKind::W1}, w1, l1, l2);
  EXPECT_NEAR(s[0], iso1 * (l1 * l1 - l3 * l3) + fib1 * l1 * l1, 1e-12 * std::abs(s[0]));
  EXPECT_NEAR(s[1], iso1 * (l2 * l2 - l3 * l3), 1e-12 * std::abs(s[1]));

  const double mu = 1.18, c0 = 55.04, c1 = 8.08, c2 = 54.0;
  const double E = std::exp(c1 * (I1 - 3) * (I1 - 3) + c2 * std::pow(I4 - 1, 4));
  const double iso2 = 2 * mu + 4 * c0 * c1 * (I1 - 3) * E, fib2 = 8 * c0 * c2 * std::pow(I4 - 1, 3) * E;
  const double w2[] = {mu, c0, c1, c2};
  s = biaxial_cauchy<double>({LawKind::W2}, w2, l1, l2);
  EXPECT_NEAR(s[0], iso2 * (l1 * l1 - l3 * l3) + fib2 * l1 * l1, 1e-12 * std::abs(s[0]));
  EXPECT_NEAR(s[1], iso2 * (l2 * l2 - l3 * l3), 1e-12 * std::abs(s[1]));

  const double C1 = 19.59, a = 12.94, b = 77.79;
  const double fib3 = 2 * a * (I4 - 1) * std::exp(b * (I4 - 1) * (I4 - 1));
  const double w3[] = {C1, a, b};
  s = biaxial_cauchy<double>({LawKind::W3}, w3, l1, l2);
  EXPECT_NEAR(s[0], 2 * C1 * (l1 * l1 - l3 * l3) + fib3 * l1 * l1, 1e-12 * std::abs(s[0]));
  EXPECT_NEAR(s[1], 2 * C1 * (l2 * l2 - l3 * l3), 1e-12 * std::abs(s[1]));
}

} // namespace
} // namespace ibvalve::materials
