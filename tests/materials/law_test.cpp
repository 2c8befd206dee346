// Every law, alone and with each volumetric penalty: P against a central difference of W, the tangent
// against a central difference of P, frame indifference, the stress-free reference state and a
// symmetric Cauchy stress. The figures measured are printed (max relative errors over the samples).
#include <cmath>
#include <iostream>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "base/units.hpp"
#include "materials/law.hpp"
#include "materials/material.hpp"

namespace ibvalve::materials {
namespace {

constexpr double kPa = units::kPa;

struct LawCase {
  std::string label;
  std::shared_ptr<const StrainEnergy> energy;
  FiberFrame frame;
  double modulus_scale; // a typical modulus (dyn/cm^2) for absolute tolerances
};

FiberFrame two_families(double degrees)
{
  const double t = degrees * M_PI / 180.0;
  FiberFrame frame;
  frame.f0 = Vec3(std::cos(t), std::sin(t), 0.0);
  frame.s0 = Vec3(std::cos(t), -std::sin(t), 0.0);
  return frame;
}

FiberFrame oblique_fiber()
{
  FiberFrame frame;
  frame.f0 = Vec3(1.0, 0.4, -0.3).normalized();
  frame.s0 = Vec3(-0.4, 1.0, 0.0).normalized();
  return frame;
}

std::shared_ptr<const StrainEnergy> law(LawKind kind, std::vector<double> p, FiberCompression fc)
{
  return std::make_shared<InvariantLaw>(kind, std::move(p), LawOptions{fc, ReferenceState::pressure_like});
}

std::vector<LawCase> cases()
{
  std::vector<LawCase> out;
  for (const auto fc : {FiberCompression::excluded, FiberCompression::included}) {
    const std::string suffix =
        fc == FiberCompression::excluded ? "_fibers_tension_only" : "_fibers_both_ways";
    // Study parameters (docs/reference.md, "Constitutive laws"), converted to CGS.
    out.push_back(
        {"neo_hookean" + suffix, law(LawKind::neo_hookean, {50.0 * kPa}, fc), oblique_fiber(), 50 * kPa});
    out.push_back({"W1" + suffix, law(LawKind::W1, {1.21 * kPa, 7.99, 24.23 * kPa, 57.62}, fc),
                   oblique_fiber(), 24.23 * kPa});
    out.push_back({"W2" + suffix, law(LawKind::W2, {1.18 * kPa, 55.04 * kPa, 8.08, 54.0}, fc),
                   oblique_fiber(), 55.04 * kPa});
    out.push_back({"W3" + suffix, law(LawKind::W3, {19.59 * kPa, 12.94 * kPa, 77.79}, fc), oblique_fiber(),
                   19.59 * kPa});
    // HGO with the adventitia-like values of Holzapfel et al. 2000 and dispersion of Gasser et al. 2006.
    out.push_back({"hgo_aligned" + suffix, law(LawKind::hgo, {3.0 * kPa, 2.3632 * kPa, 0.8393, 0.0}, fc),
                   two_families(49.98), 3 * kPa});
    out.push_back({"hgo_dispersed" + suffix, law(LawKind::hgo, {7.64 * kPa, 996.6 * kPa, 524.6, 0.226}, fc),
                   two_families(49.98), 996.6 * kPa});
  }
  // The isochoric first invariant J^(-2/3) I1 (LawOptions::isotropic_invariant), each law, fibers in
  // tension only.
  const LawOptions isochoric{FiberCompression::excluded, ReferenceState::pressure_like,
                             IsotropicInvariant::isochoric};
  auto isochoric_law = [&](LawKind kind, std::vector<double> p) {
    return std::make_shared<InvariantLaw>(kind, std::move(p), isochoric);
  };
  out.push_back({"neo_hookean_isochoric", isochoric_law(LawKind::neo_hookean, {50.0 * kPa}), oblique_fiber(),
                 50 * kPa});
  out.push_back({"W1_isochoric", isochoric_law(LawKind::W1, {1.21 * kPa, 7.99, 24.23 * kPa, 57.62}),
                 oblique_fiber(), 24.23 * kPa});
  out.push_back({"W2_isochoric", isochoric_law(LawKind::W2, {1.18 * kPa, 55.04 * kPa, 8.08, 54.0}),
                 oblique_fiber(), 55.04 * kPa});
  out.push_back({"W3_isochoric", isochoric_law(LawKind::W3, {19.59 * kPa, 12.94 * kPa, 77.79}),
                 oblique_fiber(), 19.59 * kPa});
  out.push_back({"hgo_dispersed_isochoric",
                 isochoric_law(LawKind::hgo, {7.64 * kPa, 996.6 * kPa, 524.6, 0.226}), two_families(49.98),
                 996.6 * kPa});
  // Each penalty on W1 (the composite Material).
  for (const auto kind : {PenaltyKind::log, PenaltyKind::quadratic_log, PenaltyKind::quadratic}) {
    auto w1 = law(LawKind::W1, {1.21 * kPa, 7.99, 24.23 * kPa, 57.62}, FiberCompression::excluded);
    out.push_back({"W1_plus_" + penalty_name(kind) + "_penalty",
                   std::make_shared<Material>(w1, VolumetricPenalty(kind, 1000.0 * kPa)), oblique_fiber(),
                   1000 * kPa});
  }
  for (auto& c : out)
    for (char& ch : c.label)
      if (ch == '-') ch = '_';
  return out;
}

/// Deformation gradients around the reference: random ones with det F > 0, away from the fiber
/// switch I4 = 1 (where the tension-only laws are not differentiable).
std::vector<Mat3> sample_deformations(const FiberFrame& frame)
{
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u(-0.15, 0.15);
  std::vector<Mat3> Fs;
  while (Fs.size() < 24) {
    Mat3 F = Mat3::Identity();
    for (int i = 0; i < 9; ++i) F.data()[i] += u(rng);
    const Mat3 C = F.transpose() * F;
    const double I4 = frame.f0.dot(C * frame.f0), I6 = frame.s0.dot(C * frame.s0);
    if (F.determinant() < 0.5 || std::abs(I4 - 1.0) < 1e-3 || std::abs(I6 - 1.0) < 1e-3) continue;
    // Alternate fiber tension and compression, so that both branches of the switch are checked.
    if ((I4 > 1.0) != (Fs.size() % 2 == 0)) continue;
    Fs.push_back(F);
  }
  return Fs;
}

double relative(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b)
{
  return (a - b).norm() / b.norm();
}

class LawTest : public ::testing::TestWithParam<LawCase> {};

TEST_P(LawTest, StressIsTheCentralDifferenceOfTheEnergy)
{
  const auto& c = GetParam();
  double worst = 0.0;
  for (const Mat3& F : sample_deformations(c.frame)) {
    Mat3 P_fd;
    for (int i = 0; i < 9; ++i) {
      const double h = 1e-6;
      Mat3 Fp = F, Fm = F;
      Fp.data()[i] += h;
      Fm.data()[i] -= h;
      P_fd.data()[i] = (c.energy->energy(Fp, c.frame) - c.energy->energy(Fm, c.frame)) / (2 * h);
    }
    worst = std::max(worst, relative(c.energy->stress(F, c.frame), P_fd));
  }
  std::cout << c.label << ": max |P - dW/dF (central FD)| / |P| = " << worst << "\n";
  EXPECT_LT(worst, 1e-6);
}

TEST_P(LawTest, TangentIsTheCentralDifferenceOfTheStress)
{
  const auto& c = GetParam();
  double worst = 0.0;
  for (const Mat3& F : sample_deformations(c.frame)) {
    Tangent T_fd;
    for (int j = 0; j < 9; ++j) {
      const double h = 1e-6;
      Mat3 Fp = F, Fm = F;
      Fp.data()[j] += h;
      Fm.data()[j] -= h;
      const Mat3 dP = (c.energy->stress(Fp, c.frame) - c.energy->stress(Fm, c.frame)) / (2 * h);
      T_fd.col(j) = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(dP.data());
    }
    worst = std::max(worst, relative(c.energy->tangent(F, c.frame), T_fd));
    // The combined call gives the same as the separate ones.
    Mat3 P;
    Tangent T;
    c.energy->stress_and_tangent(F, c.frame, P, T);
    EXPECT_LT(relative(P, c.energy->stress(F, c.frame)), 1e-14);
    EXPECT_LT(relative(T, c.energy->tangent(F, c.frame)), 1e-14);
  }
  std::cout << c.label << ": max |dP/dF - central FD of P| / |dP/dF| = " << worst << "\n";
  EXPECT_LT(worst, 1e-6);
}

TEST_P(LawTest, EnergyIsFrameIndifferent)
{
  const auto& c = GetParam();
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);
  double worst = 0.0;
  for (const Mat3& F : sample_deformations(c.frame)) {
    const Mat3 Q = Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
    const double W = c.energy->energy(F, c.frame);
    worst = std::max(worst, std::abs(c.energy->energy(Q * F, c.frame) - W) / std::max(std::abs(W), 1e-300));
    // and P(QF) = Q P(F)
    worst = std::max(worst, relative(c.energy->stress(Q * F, c.frame), Q * c.energy->stress(F, c.frame)));
  }
  std::cout << c.label << ": max relative change of W and of Q^T P(QF) under rotation = " << worst << "\n";
  EXPECT_LT(worst, 1e-12);
}

TEST_P(LawTest, ReferenceStateIsStressFree)
{
  const auto& c = GetParam();
  const Mat3 P = c.energy->stress(Mat3::Identity(), c.frame);
  EXPECT_LT(P.norm(), 1e-12 * c.modulus_scale) << P;
  EXPECT_NEAR(c.energy->energy(Mat3::Identity(), c.frame), 0.0, 1e-12 * c.modulus_scale);
}

TEST_P(LawTest, CauchyStressIsSymmetric)
{
  const auto& c = GetParam();
  for (const Mat3& F : sample_deformations(c.frame)) {
    const Mat3 sigma = c.energy->stress(F, c.frame) * F.transpose() / F.determinant();
    EXPECT_LT((sigma - sigma.transpose()).norm(), 1e-13 * sigma.norm());
  }
}

INSTANTIATE_TEST_SUITE_P(Laws, LawTest, ::testing::ValuesIn(cases()),
                         [](const auto& info) { return info.param.label; });

TEST(ReferenceState, AsWrittenTheIsotropicPartsCarryTheHydrostaticStressTheCorrectionRemoves)
{
  // W1: P(I) = 2 C10 C01 I as written (docs/reference.md, "Constitutive laws"); W2: 2 mu I; W3: 2 C1 I;
  // neo-Hookean: mu I.
  const LawOptions raw{FiberCompression::excluded, ReferenceState::as_written};
  const FiberFrame frame = oblique_fiber();
  const Mat3 I = Mat3::Identity();
  const InvariantLaw w1(LawKind::W1, {1.21 * kPa, 7.99, 24.23 * kPa, 57.62}, raw);
  EXPECT_LT((w1.stress(I, frame) - 2 * 1.21 * kPa * 7.99 * I).norm(), 1e-9);
  const InvariantLaw w2(LawKind::W2, {1.18 * kPa, 55.04 * kPa, 8.08, 54.0}, raw);
  EXPECT_LT((w2.stress(I, frame) - 2 * 1.18 * kPa * I).norm(), 1e-9);
  const InvariantLaw w3(LawKind::W3, {19.59 * kPa, 12.94 * kPa, 77.79}, raw);
  EXPECT_LT((w3.stress(I, frame) - 2 * 19.59 * kPa * I).norm(), 1e-9);
  const InvariantLaw nh(LawKind::neo_hookean, {50.0 * kPa}, raw);
  EXPECT_LT((nh.stress(I, frame) - 50.0 * kPa * I).norm(), 1e-9);

  // The corrected law differs from the raw one by a hydrostatic Cauchy stress only (-2 d1_ref / J I).
  const InvariantLaw w1c(LawKind::W1, {1.21 * kPa, 7.99, 24.23 * kPa, 57.62});
  EXPECT_DOUBLE_EQ(w1c.reference_d1(), 1.21 * kPa * 7.99);
  for (const Mat3& F : sample_deformations(frame)) {
    const double J = F.determinant();
    const Mat3 dsigma = (w1c.stress(F, frame) - w1.stress(F, frame)) * F.transpose() / J;
    EXPECT_LT((dsigma + 2 * w1c.reference_d1() / J * I).norm(), 1e-9 * w1c.reference_d1());
  }
}

TEST(IsotropicInvariant, IsochoricEqualsTheLawAsWrittenOnIsochoricMotions)
{
  // J = 1: I1bar = I1, so energy and deviatoric stress are the law's; only the hydrostatic part
  // differs (the reference term of the I1 form, -2 d1_ref I, against none), which the fluid's pressure
  // takes in an incompressible model. Every biaxial fit and result is therefore the same.
  const LawOptions isochoric{FiberCompression::excluded, ReferenceState::pressure_like,
                             IsotropicInvariant::isochoric};
  const FiberFrame frame = oblique_fiber();
  for (const auto kind : {LawKind::W1, LawKind::W2, LawKind::W3}) {
    const std::vector<double> p = kind == LawKind::W1   ? std::vector{1.21 * kPa, 7.99, 24.23 * kPa, 57.62}
                                  : kind == LawKind::W2 ? std::vector{1.18 * kPa, 55.04 * kPa, 8.08, 54.0}
                                                        : std::vector{19.59 * kPa, 12.94 * kPa, 77.79};
    const InvariantLaw as_written(kind, p), bar(kind, p, isochoric);
    EXPECT_EQ(bar.reference_d1(), 0.0);
    for (const Mat3& F0 : sample_deformations(frame)) {
      const Mat3 F = F0 / std::cbrt(F0.determinant()); // J = 1
      EXPECT_NEAR(bar.energy(F, frame), as_written.energy(F, frame),
                  1e-9 * std::abs(as_written.energy(F, frame)));
      const Mat3 s1 = bar.stress(F, frame) * F.transpose(), s2 = as_written.stress(F, frame) * F.transpose();
      const Mat3 d1 = s1 - s1.trace() / 3.0 * Mat3::Identity(), d2 = s2 - s2.trace() / 3.0 * Mat3::Identity();
      EXPECT_LT((d1 - d2).norm(), 1e-9 * d2.norm());
    }
  }
}

TEST(IsotropicInvariant, IsochoricResistsTheFlatteningOfAPoint)
{
  // F = diag(1, 1, e), fibers along x (unstretched, so the fiber term is off): as e -> 0 the I1 form's
  // isotropic energy falls (I1 = 2 + e^2 < 3) and only its reference term -2 d1_ref ln e rises, while
  // J^(-2/3) I1 = e^(-2/3) (2 + e^2) makes W1's exponential grow without bound.
  FiberFrame frame;
  frame.f0 = Vec3::UnitX();
  const std::vector<double> w1{1.21 * kPa, 7.99, 24.23 * kPa, 57.62};
  const InvariantLaw as_written(LawKind::W1, w1),
      bar(LawKind::W1, w1,
          {FiberCompression::excluded, ReferenceState::pressure_like, IsotropicInvariant::isochoric});
  // (e = 0.5: 115 against 12 kPa; e = 0.3: 7e5 against 22 kPa.)
  for (const double e : {0.5, 0.3, 0.1}) {
    const Mat3 F = Eigen::Vector3d(1.0, 1.0, e).asDiagonal();
    const double c10 = w1[0], c01 = w1[1];
    EXPECT_NEAR(bar.energy(F, frame), c10 * std::expm1(c01 * (std::pow(e, -2.0 / 3.0) * (2.0 + e * e) - 3.0)),
                1e-9 * bar.energy(F, frame));
    EXPECT_NEAR(as_written.energy(F, frame),
                c10 * std::expm1(c01 * (e * e - 1.0)) - 2.0 * c10 * c01 * std::log(e), 1e-6 * c10);
    EXPECT_GT(bar.energy(F, frame), 5.0 * as_written.energy(F, frame)) << "e = " << e;
  }
}

TEST(FiberCompression, ExcludedFibersCarryNoStressWhenShortened)
{
  // Shorten along the fiber (I4 < 1): W1 and W3 then equal their isotropic parts; with the fibers
  // included the fiber term adds a compressive fiber stress.
  FiberFrame frame;
  frame.f0 = Vec3::UnitX();
  const Mat3 F = Eigen::Vector3d(0.9, 1.05, 1.0 / (0.9 * 1.05)).asDiagonal();
  const InvariantLaw w1_off(LawKind::W1, {1.21 * kPa, 7.99, 24.23 * kPa, 57.62});
  const InvariantLaw w1_iso(LawKind::W1, {1.21 * kPa, 7.99, 0.0, 57.62});
  const InvariantLaw w1_on(LawKind::W1, {1.21 * kPa, 7.99, 24.23 * kPa, 57.62},
                           {FiberCompression::included, ReferenceState::pressure_like});
  EXPECT_LT((w1_off.stress(F, frame) - w1_iso.stress(F, frame)).norm(), 1e-9);
  EXPECT_LT(w1_on.stress(F, frame)(0, 0), w1_off.stress(F, frame)(0, 0) - 1e3);
  // W2: the fiber part of the exponent is dropped.
  const InvariantLaw w2_off(LawKind::W2, {1.18 * kPa, 55.04 * kPa, 8.08, 54.0});
  const InvariantLaw w2_iso(LawKind::W2, {1.18 * kPa, 55.04 * kPa, 8.08, 0.0});
  EXPECT_LT((w2_off.stress(F, frame) - w2_iso.stress(F, frame)).norm(), 1e-9);
  // In tension the switch changes nothing.
  const Mat3 G = Eigen::Vector3d(1.1, 1.0, 1.0 / 1.1).asDiagonal();
  EXPECT_LT((w1_on.stress(G, frame) - w1_off.stress(G, frame)).norm(), 1e-9);
}

TEST(Penalty, PureDilatationGivesTheAnalyticPressure)
{
  // F = s I: P_vol = J U'(J) F^{-T} = J U'(J)/s I with J = s^3, for each form.
  const double kappa = 1000.0 * kPa, s = 1.05, J = s * s * s;
  const FiberFrame frame;
  const Mat3 F = s * Mat3::Identity();
  const double expected_log = kappa * std::log(J) / J;
  const double expected_quadratic_log = 0.5 * kappa * (J - 1.0 / J);
  const double expected_quadratic = kappa * (J - 1.0);
  EXPECT_NEAR(VolumetricPenalty(PenaltyKind::log, kappa).stress(F, frame)(0, 0), J * expected_log / s,
              1e-9 * kappa);
  EXPECT_NEAR(VolumetricPenalty(PenaltyKind::quadratic_log, kappa).stress(F, frame)(1, 1),
              J * expected_quadratic_log / s, 1e-9 * kappa);
  EXPECT_NEAR(VolumetricPenalty(PenaltyKind::quadratic, kappa).stress(F, frame)(2, 2),
              J * expected_quadratic / s, 1e-9 * kappa);
  EXPECT_EQ(VolumetricPenalty(PenaltyKind::none, kappa).stress(F, frame).norm(), 0.0);
  // Isochoric motions feel no penalty.
  const Mat3 G = Eigen::Vector3d(1.2, 1.0 / 1.2, 1.0).asDiagonal();
  EXPECT_LT(VolumetricPenalty(PenaltyKind::log, kappa).stress(G, frame).norm(), 1e-9);
}

} // namespace
} // namespace ibvalve::materials
