// Case-file materials (materials/settings.hpp): presets in kPa become CGS laws, explicit keys override
// them, and every inconsistent choice is one InputError line naming file:line and key.
#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "base/errors.hpp"
#include "base/units.hpp"
#include "materials/settings.hpp"

namespace ibvalve::materials {
namespace {

/// A case holding one material table, leaflet.material, validated against the keys its bind declares.
io::Config material_case(const std::string& toml_text)
{
  io::Schema schema;
  io::KeyBinder declaring(schema);
  MaterialKeys unused;
  bind(declaring, unused, "leaflet.material");
  return io::Config::validate(toml::parse(std::string_view{toml_text}, std::string_view{"case.toml"}),
                              "case.toml", schema);
}

MaterialSettings read(const std::string& toml_text)
{
  const io::Config config = material_case(toml_text);
  io::KeyBinder keys(config);
  MaterialKeys k;
  bind(keys, k, "leaflet.material");
  return material_settings(keys, k);
}

std::string error_of(const std::string& toml_text)
{
  try {
    read(toml_text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(MaterialSettings, PresetGivesTheStudysParametersInCgs)
{
  const auto s = read("[leaflet.material]\npreset = \"zhu2021-W1\"\n");
  EXPECT_EQ(s.law, LawKind::W1);
  ASSERT_EQ(s.parameters.size(), 4u);
  EXPECT_DOUBLE_EQ(s.parameters[0], 1.21 * units::kPa);
  EXPECT_DOUBLE_EQ(s.parameters[1], 7.99);
  EXPECT_DOUBLE_EQ(s.parameters[2], 24.23 * units::kPa);
  EXPECT_DOUBLE_EQ(s.parameters[3], 57.62);
  EXPECT_EQ(s.options.fiber_compression, FiberCompression::excluded);
  EXPECT_EQ(s.penalty, PenaltyKind::log);
  EXPECT_DOUBLE_EQ(s.bulk_modulus, 1000.0 * units::kPa);
  const auto material = s.build();
  FiberFrame frame;
  frame.f0 = Vec3::UnitX();
  EXPECT_LT(material->stress(Mat3::Identity(), frame).norm(), 1e-9);
}

TEST(MaterialSettings, ExplicitKeysOverrideThePresetAndChooseEveryOption)
{
  const auto s = read("[leaflet.material]\npreset = \"zhu2021-W3\"\nlaw = \"W3\"\nb = 70.0\na = 10\n"
                      "fiber_compression = \"on\"\npenalty = \"quadratic-log\"\nbulk_modulus = 500.0\n");
  EXPECT_EQ(s.law, LawKind::W3);
  EXPECT_DOUBLE_EQ(s.parameters[0], 19.59 * units::kPa);
  EXPECT_DOUBLE_EQ(s.parameters[1], 10.0 * units::kPa);
  EXPECT_DOUBLE_EQ(s.parameters[2], 70.0);
  EXPECT_EQ(s.options.fiber_compression, FiberCompression::included);
  EXPECT_EQ(s.penalty, PenaltyKind::quadratic_log);
  EXPECT_DOUBLE_EQ(s.bulk_modulus, 500.0 * units::kPa);
  EXPECT_NE(s.describe().find("W3 (C1 = 19.59 kPa, a = 10 kPa, b = 70)"), std::string::npos) << s.describe();
}

TEST(MaterialSettings, ExplicitParametersWithoutPreset)
{
  const auto s = read("[leaflet.material]\nlaw = \"hgo\"\nmu = 3.0\nk1 = 2.3632\nk2 = 0.8393\nkappa = 0.2\n"
                      "penalty = \"none\"\n");
  EXPECT_EQ(s.law, LawKind::hgo);
  EXPECT_DOUBLE_EQ(s.parameters[3], 0.2);
  EXPECT_EQ(s.penalty, PenaltyKind::none);
}

TEST(MaterialSettings, InconsistentChoicesNameFileLineAndKey)
{
  EXPECT_EQ(error_of("[leaflet.material]\nlaw = \"W3\"\nC1 = 1\na = 1\nb = 1\nC10 = 2\n"),
            "case.toml:6: leaflet.material.C10: not a parameter of law W3 (its parameters: C1, a, b)");
  EXPECT_EQ(error_of("[leaflet.material]\nlaw = \"W2\"\npreset = \"zhu2021-W1\"\n"),
            "case.toml:3: leaflet.material.preset: preset \"zhu2021-W1\" is for law W1, not W2");
  EXPECT_EQ(error_of("[leaflet.material]\nlaw = \"W3\"\nC1 = 1\na = 1\n"),
            "case.toml:2: leaflet.material.law: law W3 needs parameter b (give it, or a preset)");
  EXPECT_EQ(error_of("[leaflet.material]\npenalty = \"log\"\n").rfind("case.toml", 0), 0u);
  // Ranges come from the schema: kappa <= 1/3, parameters >= 0.
  EXPECT_NE(error_of("[leaflet.material]\nlaw = \"hgo\"\nmu = 1\nk1 = 1\nk2 = 1\nkappa = 0.5\n")
                .find("case.toml:6: leaflet.material.kappa: 0.5 is out of range"),
            std::string::npos);
  EXPECT_NE(
      error_of("[leaflet.material]\nlaw = \"W1\"\nC10 = -1\n").find("case.toml:3: leaflet.material.C10"),
      std::string::npos);
}

TEST(MaterialSettings, EveryPresetBuildsAStressFreeMaterial)
{
  for (const Preset& preset : presets()) {
    MaterialSettings s;
    s.law = preset.law;
    s.parameters = to_cgs(preset.law, preset.values);
    const auto material = s.build();
    FiberFrame frame;
    frame.f0 = Vec3::UnitX();
    frame.s0 = Vec3::UnitY();
    EXPECT_LT(material->stress(Mat3::Identity(), frame).norm(), 1e-9) << preset.name;
    EXPECT_EQ(to_user_units(preset.law, s.parameters), preset.values) << preset.name;
  }
}

// law = "expression": the formula and its parameters, moduli in kPa.
const std::string w1_formula =
    "[leaflet.material]\nlaw = \"expression\"\n"
    "energy = \"C10*(exp(C01*(I1 - 3)) - 1) + k1/(2*k2)*(exp(k2*(I4 - 1)^2) - 1)\"\n"
    "parameters = { C10 = 1.21, C01 = 7.99, k1 = 24.23, k2 = 57.62 }\n"
    "moduli = [\"C10\", \"k1\"]\n";

TEST(MaterialSettings, AnExpressionLawTakesItsModuliInKpaAndBuildsTheLawItWrites)
{
  const MaterialSettings s = read(w1_formula);
  ASSERT_TRUE(s.expression);
  ASSERT_EQ(s.expression->parameters.size(), 4u);
  EXPECT_EQ(s.expression->parameters[1].name, "C10");
  EXPECT_DOUBLE_EQ(s.expression->parameters[1].value, 1.21 * units::kPa);
  EXPECT_DOUBLE_EQ(s.expression->parameters[0].value, 7.99); // C01: dimensionless
  EXPECT_TRUE(s.warnings.empty());
  EXPECT_NE(s.describe().find("C10 = 1.21 kPa, k1 = 24.23 kPa, k2 = 57.62)"), std::string::npos)
      << s.describe();
  // The same material as the built-in W1 of the same parameters.
  MaterialSettings w1 = read("[leaflet.material]\npreset = \"zhu2021-W1\"\n");
  FiberFrame frame;
  frame.f0 = Vec3(1.0, 0.2, 0.0).normalized();
  Mat3 F;
  F << 1.12, 0.05, 0.0, -0.02, 0.93, 0.03, 0.01, 0.0, 0.97;
  const Mat3 P = s.build()->stress(F, frame), P_w1 = w1.build()->stress(F, frame);
  EXPECT_LT((P - P_w1).norm(), 1e-13 * P_w1.norm());
}

/// The error line for `w1_formula` with `from` replaced by `to`.
std::string error_with(const std::string& from, const std::string& to)
{
  std::string text = w1_formula;
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return error_of(text.replace(at, from.size(), to));
}

TEST(MaterialSettings, EachMistakeInAnExpressionLawNamesFileLineKeyAndCharacter)
{
  EXPECT_EQ(error_with("(I1 - 3))", "(I1 - 3)"),
            "case.toml:3: leaflet.material.energy: character 5: ')' missing: the formula ends before it");
  EXPECT_EQ(error_with("C01*(I1", "C01*(I5"),
            "case.toml:3: leaflet.material.energy: character 15: unknown symbol 'I5' (known: I1, I1bar, I2, "
            "I4, I6, I8, J, C01, C10, k1, k2)");
  EXPECT_EQ(
      error_with("exp(C01", "expo(C01"),
      "case.toml:3: leaflet.material.energy: character 6: unknown function 'expo' (functions: exp, log, "
      "sqrt, abs, step, pow, min, max)");
  EXPECT_EQ(error_with(", k2 = 57.62 }", ", k2 = 57.62, k3 = 1.0 }"),
            "case.toml:4: leaflet.material.parameters.k3: not used in the energy");
  EXPECT_EQ(error_with("[\"C10\", \"k1\"]", "[\"C10\", \"k1\", \"k9\"]"),
            "case.toml:5: leaflet.material.moduli: 'k9' is not one of the parameters (C01, C10, k1, k2)");
  EXPECT_EQ(error_with("C10 = 1.21,", "I4 = 1.21, C10 = 1.21,"),
            "case.toml:4: leaflet.material.parameters.I4: 'I4' is an invariant, not a parameter");
  EXPECT_EQ(
      error_with("[\"C10\", \"k1\"]", "[\"C10\"]"),
      "case.toml:3: leaflet.material.energy: the energy is not a stress in the moduli (C10): doubling them "
      "does not double it. List in `moduli` every parameter given in kPa, and only those (the others are "
      "dimensionless)");
  EXPECT_EQ(
      error_with("(I4 - 1)^2", "log(I4 - 1)"),
      "case.toml:3: leaflet.material.energy: character 49: the energy or its derivatives are not finite at "
      "I1 = 3, I4 = 1, J = 1 (F = diag(1, 1, 1))");
  EXPECT_EQ(
      error_with("(I4 - 1)^2", "(I4 - 1)"),
      "case.toml:3: leaflet.material.energy: character 50: the stress at F = I is not zero: dW/dI4 = 12.115 "
      "kPa there (I4 = I6 = 1, I8 = 0); a fiber term must vanish with its slope at the reference, e.g. (I4 "
      "- 1)^2");
  EXPECT_EQ(
      error_with("law = \"expression\"\n", "law = \"expression\"\nk1 = 2.0\n"),
      "case.toml:3: leaflet.material.k1: not a key of law expression (its parameters go in `parameters = "
      "{ ... }`)");
  EXPECT_EQ(
      error_of("[leaflet.material]\nlaw = \"expression\"\n"),
      "case.toml:2: leaflet.material.law: law expression needs `energy`, a formula of the invariants, and "
      "its `parameters` (or a preset, whose law's formula it takes)");
  EXPECT_EQ(error_of("[leaflet.material]\nlaw = \"W3\"\nC1 = 1\na = 1\nb = 1\nenergy = \"a\"\n"),
            "case.toml:6: leaflet.material.energy: only for law = \"expression\" (law W3 is built in)");
}

/// The largest relative difference of W, P and dP/dF between two materials over deformations with
/// both fiber families stretched or shortened.
double largest_difference(const Material& a, const Material& b)
{
  FiberFrame frame;
  frame.f0 = Vec3(1.0, 0.4, -0.3).normalized();
  frame.s0 = Vec3(0.9, -0.5, 0.2).normalized();
  double worst = 0.0;
  for (int k = 0; k < 12; ++k) {
    Mat3 F = Mat3::Identity();
    for (int i = 0; i < 9; ++i) F.data()[i] += 0.15 * std::sin(1.7 * (k + 1) * (i + 2)); // det F > 0.5
    Mat3 Pa, Pb;
    Tangent Ta, Tb;
    a.stress_and_tangent(F, frame, Pa, Ta);
    b.stress_and_tangent(F, frame, Pb, Tb);
    const double Wa = a.energy(F, frame), Wb = b.energy(F, frame);
    worst = std::max({worst, std::abs(Wa - Wb) / std::abs(Wb), (Pa - Pb).norm() / Pb.norm(),
                      (Ta - Tb).norm() / Tb.norm()});
  }
  return worst;
}

TEST(MaterialSettings, EveryPresetTakenAsAnExpressionIsTheBuiltInPresetToRoundOff)
{
  for (const Preset& preset : presets())
    for (const char* fibers : {"off", "on"}) {
      const std::string options = "fiber_compression = \"" + std::string(fibers) + "\"\n";
      const std::string table = "[leaflet.material]\npreset = \"" + preset.name + "\"\n" + options;
      const MaterialSettings formula = read(table + "law = \"expression\"\n");
      const MaterialSettings built_in = read(table);
      ASSERT_TRUE(formula.expression) << preset.name;
      EXPECT_EQ(formula.expression->energy, law_info(preset.law).energy);
      EXPECT_NE(formula.describe().find("from preset " + preset.name), std::string::npos)
          << formula.describe();
      EXPECT_LT(largest_difference(*formula.build(), *built_in.build()), 1e-12)
          << preset.name << ", " << fibers;
    }
}

TEST(MaterialSettings, APresetsFormulaTakesParametersAndAnEnergyThatOverrideIt)
{
  // A parameter given overrides the preset's (a modulus in kPa, as the law's moduli are).
  const MaterialSettings changed = read("[leaflet.material]\npreset = \"zhu2021-W1\"\nlaw = \"expression\"\n"
                                        "parameters = { k1 = 30.0, k2 = 40.0 }\n");
  const MaterialSettings built_in =
      read("[leaflet.material]\npreset = \"zhu2021-W1\"\nk1 = 30.0\nk2 = 40.0\n");
  EXPECT_LT(largest_difference(*changed.build(), *built_in.build()), 1e-12);
  // An energy of one's own that reads the preset's parameters (here W1 with its fiber term stiffened
  // in I4's square root, the fiber stretch).
  const MaterialSettings own =
      read("[leaflet.material]\npreset = \"zhu2021-W1\"\nlaw = \"expression\"\n"
           "energy = \"C10*(exp(C01*(I1 - 3)) - 1) + k1/(2*k2)*(exp(k2*(sqrt(I4) - 1)^2) - 1)\"\n");
  EXPECT_EQ(own.expression->parameters.size(), 4u);
  // One that leaves a preset's parameter out names it.
  EXPECT_EQ(error_of("[leaflet.material]\npreset = \"zhu2021-W1\"\nlaw = \"expression\"\n"
                     "energy = \"C10*(exp(C01*(I1 - 3)) - 1)\"\n"),
            "case.toml:4: leaflet.material.energy: parameter k1 of preset \"zhu2021-W1\" is not used in the "
            "energy");
}

TEST(MaterialSettings, AnExpressionReadingFibersThePartLacksIsAnInputError)
{
  const std::string text = w1_formula;
  const io::Config config = material_case(text);
  io::KeyBinder keys(config);
  MaterialKeys k;
  bind(keys, k, "leaflet.material");
  const MaterialSettings s = material_settings(keys, k);
  EXPECT_NO_THROW(check_fiber_families(s, 1, keys, k));
  try {
    check_fiber_families(s, 0, keys, k);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "case.toml:3: leaflet.material.energy: character 50: the energy reads a fiber "
                           "invariant, but this part has no fibers");
  }
}

TEST(MaterialSettings, AnEnergyThatLosesConvexityAlongTheFitsPathsIsWarnedAbout)
{
  const MaterialSettings s =
      read("[leaflet.material]\nlaw = \"expression\"\nenergy = \"mu*(I1 - 3) - k*(I4 - 1)^2\"\n"
           "parameters = { mu = 1.0, k = 10.0 }\nmoduli = [\"mu\", \"k\"]\nfiber_compression = \"on\"\n");
  ASSERT_FALSE(s.warnings.empty());
  EXPECT_EQ(s.warnings[0].rfind("case.toml:3: leaflet.material.energy: the energy is not convex along the "
                                "equibiaxial stretch",
                                0),
            0u)
      << s.warnings[0];
}

} // namespace
} // namespace ibvalve::materials
