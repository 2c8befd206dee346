// Laws written as formulas (materials/expression_law.hpp): the five built-in laws written out give
// the built-in kernels' W, P and dP/dF to round-off on random deformations with fibers, with every
// option; the invariants no built-in law reads (I2, I8, J, I1bar) are checked against central
// differences; the reference term leaves F = I stress free. The figures measured are printed.
#include <cmath>
#include <iostream>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "base/units.hpp"
#include "materials/expression_checks.hpp"
#include "materials/expression_law.hpp"
#include "materials/material.hpp"

namespace ibvalve::materials {
namespace {

constexpr double kPa = units::kPa;

struct BuiltIn {
  const char* label;
  LawKind kind;
  std::vector<double> values; // CGS
  std::string energy;
  std::vector<ExpressionParameter> parameters;
};

/// The built-in laws of law_kernels.hpp written as formulas, with the study's and the classic
/// parameters (the built-in hgo drops a compressed family's whole term: step(I_i - 1), fibers on).
std::vector<BuiltIn> built_ins()
{
  const std::string hgo_family = "k1/(2*k2)*(exp(k2*(kappa*(I1 - 3) + (1 - 3*kappa)*(I@ - 1))^2) - 1)";
  auto family = [&](const char* i) {
    std::string t = hgo_family;
    t.replace(t.find('@'), 1, i);
    return t;
  };
  return {
      {"neo-Hookean", LawKind::neo_hookean, {50 * kPa}, "mu/2*(I1 - 3)", {{"mu", 50 * kPa, true}}},
      {"W1",
       LawKind::W1,
       {1.21 * kPa, 7.99, 24.23 * kPa, 57.62},
       "C10*(exp(C01*(I1 - 3)) - 1) + k1/(2*k2)*(exp(k2*(I4 - 1)^2) - 1)",
       {{"C10", 1.21 * kPa, true}, {"C01", 7.99, false}, {"k1", 24.23 * kPa, true}, {"k2", 57.62, false}}},
      {"W2",
       LawKind::W2,
       {1.18 * kPa, 55.04 * kPa, 8.08, 54.0},
       "mu*(I1 - 3) + c0*(exp(c1*(I1 - 3)^2 + c2*(I4 - 1)^4) - 1)",
       {{"mu", 1.18 * kPa, true}, {"c0", 55.04 * kPa, true}, {"c1", 8.08, false}, {"c2", 54.0, false}}},
      {"W3",
       LawKind::W3,
       {19.59 * kPa, 12.94 * kPa, 77.79},
       "C1*(I1 - 3) + a/(2*b)*(exp(b*(I4 - 1)^2) - 1)",
       {{"C1", 19.59 * kPa, true}, {"a", 12.94 * kPa, true}, {"b", 77.79, false}}},
      {"hgo",
       LawKind::hgo,
       {7.64 * kPa, 996.6 * kPa, 524.6, 0.226},
       "mu/2*(I1 - 3) + step(I4 - 1)*" + family("4") + " + step(I6 - 1)*" + family("6"),
       {{"mu", 7.64 * kPa, true}, {"k1", 996.6 * kPa, true}, {"k2", 524.6, false}, {"kappa", 0.226, false}}},
  };
}

FiberFrame fibers()
{
  FiberFrame frame;
  frame.f0 = Vec3(1.0, 0.4, -0.3).normalized();
  frame.s0 = Vec3(0.9, -0.5, 0.2).normalized();
  return frame;
}

/// Random deformations around the reference (det F > 0.5), half with the main family stretched.
std::vector<Mat3> deformations(const FiberFrame& frame, int count = 40)
{
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  std::vector<Mat3> Fs;
  while (static_cast<int>(Fs.size()) < count) {
    Mat3 F = Mat3::Identity();
    for (int i = 0; i < 9; ++i) F.data()[i] += u(rng);
    const double I4 = frame.f0.dot(F.transpose() * F * frame.f0);
    if (F.determinant() < 0.5 || (I4 > 1.0) != (Fs.size() % 2 == 0)) continue;
    Fs.push_back(F);
  }
  return Fs;
}

double relative(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b)
{
  return (a - b).norm() / b.norm();
}

struct Worst {
  double W = 0, P = 0, T = 0;
};

/// The largest relative differences of W, P, dP/dF between two energies over `Fs`.
Worst compare(const StrainEnergy& a, const StrainEnergy& b, const FiberFrame& frame,
              const std::vector<Mat3>& Fs)
{
  Worst w;
  for (const Mat3& F : Fs) {
    Mat3 Pa, Pb;
    Tangent Ta, Tb;
    a.stress_and_tangent(F, frame, Pa, Ta);
    b.stress_and_tangent(F, frame, Pb, Tb);
    const double Wb = b.energy(F, frame);
    w.W = std::max(w.W, std::abs(a.energy(F, frame) - Wb) / std::abs(Wb));
    w.P = std::max(w.P, relative(Pa, Pb));
    w.T = std::max(w.T, relative(Ta, Tb));
    EXPECT_LT(relative(a.stress(F, frame), Pb), 1e-12);
    EXPECT_LT(relative(a.tangent(F, frame), Tb), 1e-12);
  }
  return w;
}

TEST(ExpressionLaw, TheBuiltInLawsWrittenAsFormulasGiveTheBuiltInKernelsToRoundOff)
{
  const FiberFrame frame = fibers();
  const auto Fs = deformations(frame);
  struct Options {
    const char* label;
    LawOptions options;
  };
  const std::vector<Options> variants{
      {"fibers off", {FiberCompression::excluded, ReferenceState::pressure_like, IsotropicInvariant::I1}},
      {"fibers on", {FiberCompression::included, ReferenceState::pressure_like, IsotropicInvariant::I1}},
      {"as written", {FiberCompression::excluded, ReferenceState::as_written, IsotropicInvariant::I1}},
      {"isochoric",
       {FiberCompression::excluded, ReferenceState::pressure_like, IsotropicInvariant::isochoric}}};
  Worst overall;
  for (const BuiltIn& law : built_ins())
    for (const Options& v : variants) {
      LawOptions expression_options = v.options;
      std::string energy = law.energy;
      if (law.kind == LawKind::hgo) {
        // The built-in hgo's switch is in the formula (step); with fibers on it is dropped.
        expression_options.fiber_compression = FiberCompression::included;
        if (v.options.fiber_compression == FiberCompression::included)
          for (const char* step : {"step(I4 - 1)*", "step(I6 - 1)*"}) energy.erase(energy.find(step), 13);
      }
      const auto built_in = std::make_shared<InvariantLaw>(law.kind, law.values, v.options);
      const auto expression = std::make_shared<ExpressionLaw>(energy, law.parameters, expression_options);
      const Worst alone = compare(*expression, *built_in, frame, Fs);
      // With a volumetric penalty, through Material (which adds the built-in reference term itself).
      const VolumetricPenalty penalty(PenaltyKind::log, 1000 * kPa);
      const Worst material = compare(Material(expression, penalty), Material(built_in, penalty), frame, Fs);
      std::cout << law.label << ", " << v.label << ": max relative difference W " << alone.W << ", P "
                << alone.P << ", dP/dF " << alone.T << "; with the log penalty W " << material.W << ", P "
                << material.P << ", dP/dF " << material.T << "\n";
      for (const Worst& w : {alone, material}) {
        EXPECT_LT(w.W, 1e-12) << law.label << ", " << v.label;
        EXPECT_LT(w.P, 1e-12) << law.label << ", " << v.label;
        EXPECT_LT(w.T, 1e-12) << law.label << ", " << v.label;
        overall = {std::max(overall.W, w.W), std::max(overall.P, w.P), std::max(overall.T, w.T)};
      }
    }
  std::cout << "all five laws, every option: max relative difference W " << overall.W << ", P " << overall.P
            << ", dP/dF " << overall.T << "\n";
}

/// A law reading every invariant, including those no built-in law reads.
ExpressionLaw every_invariant(LawOptions options = {})
{
  return ExpressionLaw("c1*(I1bar - 3) + c2*(I2 - 3)^2/4 + k*I8^2*exp(b*(I6 - 1)) + q*(I4 - 1)^2*I1 "
                       "+ kappa*(J - 1)^2 - c1*log(J)*0.1",
                       {{"c1", 30 * kPa, true},
                        {"c2", 5 * kPa, true},
                        {"k", 20 * kPa, true},
                        {"b", 2.0, false},
                        {"q", 10 * kPa, true},
                        {"kappa", 100 * kPa, true}},
                       options);
}

TEST(ExpressionLaw, EveryInvariantsStressAndTangentAreTheCentralDifferencesOfEnergyAndStress)
{
  const FiberFrame frame = fibers();
  for (const auto fiber : {FiberCompression::excluded, FiberCompression::included}) {
    const ExpressionLaw law = every_invariant({fiber});
    double worst_P = 0.0, worst_T = 0.0;
    for (const Mat3& F : deformations(frame, 24)) {
      Mat3 P_fd;
      Tangent T_fd;
      const double h = 1e-6;
      for (int i = 0; i < 9; ++i) {
        Mat3 Fp = F, Fm = F;
        Fp.data()[i] += h;
        Fm.data()[i] -= h;
        P_fd.data()[i] = (law.energy(Fp, frame) - law.energy(Fm, frame)) / (2 * h);
        const Mat3 dP = (law.stress(Fp, frame) - law.stress(Fm, frame)) / (2 * h);
        T_fd.col(i) = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(dP.data());
      }
      worst_P = std::max(worst_P, relative(law.stress(F, frame), P_fd));
      worst_T = std::max(worst_T, relative(law.tangent(F, frame), T_fd));
    }
    std::cout << "I1bar, I2, I4, I6, I8, J law: max |P - FD| / |P| = " << worst_P
              << ", max |dP/dF - FD| / |dP/dF| = " << worst_T << "\n";
    EXPECT_LT(worst_P, 1e-7);
    EXPECT_LT(worst_T, 1e-7);
  }
}

TEST(ExpressionLaw, TheReferenceTermRemovesTheHydrostaticStressAtTheIdentity)
{
  // P(I) = (2 c1 + 4 c2 - d) I as written; the term -p_ref ln J removes it.
  const std::vector<ExpressionParameter> p{
      {"c1", 3 * kPa, true}, {"c2", 1 * kPa, true}, {"d", 2 * kPa, true}};
  const std::string energy = "c1*(I1 - 3) + c2*(I2 - 3) - d*log(J)";
  const ExpressionLaw as_written(energy, p, {FiberCompression::excluded, ReferenceState::as_written});
  const ExpressionLaw stress_free(energy, p);
  const FiberFrame frame = fibers();
  EXPECT_NEAR((as_written.stress(Mat3::Identity(), frame) - 8 * kPa * Mat3::Identity()).norm(), 0.0, 1e-9);
  EXPECT_DOUBLE_EQ(stress_free.reference_pressure(), 8 * kPa);
  EXPECT_LT(stress_free.stress(Mat3::Identity(), frame).norm(), 1e-10 * kPa);
  EXPECT_LT(every_invariant().stress(Mat3::Identity(), FiberFrame{Vec3::UnitX(), Vec3::UnitY()}).norm(),
            1e-10 * kPa);
}

TEST(ExpressionLaw, ASlackFiberFamilyBearsNoLoadWhenCompressionIsExcluded)
{
  // Below I4 = 1 the fiber term of W1 is gone: the law equals its isotropic part.
  const ExpressionLaw w1(
      "C10*(exp(C01*(I1 - 3)) - 1) + k1/(2*k2)*(exp(k2*(I4 - 1)^2) - 1)",
      {{"C10", 1.21 * kPa, true}, {"C01", 7.99, false}, {"k1", 24.23 * kPa, true}, {"k2", 57.62, false}});
  const ExpressionLaw isotropic("C10*(exp(C01*(I1 - 3)) - 1)",
                                {{"C10", 1.21 * kPa, true}, {"C01", 7.99, false}});
  FiberFrame frame;
  frame.f0 = Vec3::UnitX();
  const Mat3 F = Vec3(0.9, 1.05, 1.0 / (0.9 * 1.05)).asDiagonal(); // I4 = 0.81
  EXPECT_LT(relative(w1.tangent(F, frame), isotropic.tangent(F, frame)), 1e-15);
  const Mat3 G = Vec3(1.1, 0.95, 1.0 / (1.1 * 0.95)).asDiagonal(); // I4 = 1.21: the fiber pulls
  EXPECT_GT((w1.stress(G, frame) - isotropic.stress(G, frame)).norm(), 1 * kPa);
}

TEST(ExpressionLaw, TheCatalogueLawsPassTheChecks)
{
  // docs/materials.md, "A catalogue of leaflet laws written as formulas" (illustrative values).
  struct Entry {
    const char* energy;
    std::vector<ExpressionParameter> parameters;
    FiberCompression fibers;
  };
  const std::vector<Entry> catalogue{
      {"c1*(I1 - 3) + c2*(I2 - 3)",
       {{"c1", 10 * kPa, true}, {"c2", 2 * kPa, true}},
       FiberCompression::excluded},
      {"c0*(exp(c1*(I1 - 3)^2 + c2*(sqrt(I4) - 1)^4) - 1)",
       {{"c0", 0.4 * kPa, true}, {"c1", 5.0, false}, {"c2", 200.0, false}},
       FiberCompression::excluded},
      {"c0/2*(I1 - 3) + c1/2*(delta*exp(c2*(I1 - 3)^2) + (1 - delta)*exp(c3*(I4 - 1)^2) - 1)",
       {{"c0", 10 * kPa, true},
        {"c1", 0.2 * kPa, true},
        {"delta", 0.1, false},
        {"c2", 10.0, false},
        {"c3", 50.0, false}},
       FiberCompression::excluded},
      {"c/2*(exp(b1*(I4 - 1)^2/4 + b2*(I6 - 1)^2/4 + b3*(I4 - 1)*(I6 - 1)/2 + b4*I8^2/4) - 1)",
       {{"c", 1 * kPa, true},
        {"b1", 40.0, false},
        {"b2", 10.0, false},
        {"b3", 5.0, false},
        {"b4", 8.0, false}},
       FiberCompression::included},
  };
  for (const Entry& e : catalogue) {
    const ExpressionLaw law(e.energy, e.parameters, {e.fibers});
    const auto problem = check_expression_law(law);
    EXPECT_FALSE(problem) << e.energy << ": " << (problem ? problem->message : "");
    EXPECT_LT(law.stress(Mat3::Identity(), FiberFrame{Vec3::UnitX(), Vec3::UnitY()}).norm(), 1e-10 * kPa);
  }
  for (const BuiltIn& b : built_ins()) {
    const ExpressionLaw law(b.energy, b.parameters, {FiberCompression::included});
    EXPECT_FALSE(check_expression_law(law)) << b.label;
  }
}

} // namespace
} // namespace ibvalve::materials
