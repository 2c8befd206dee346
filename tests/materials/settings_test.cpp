// Case-file materials (materials/settings.hpp): presets in kPa become CGS laws, explicit keys override
// them, and every inconsistent choice is one InputError line naming file:line and key.
#include <string>

#include <gtest/gtest.h>

#include "base/errors.hpp"
#include "base/units.hpp"
#include "materials/settings.hpp"

namespace ibvalve::materials {
namespace {

MaterialSettings read(const std::string& toml_text)
{
  const io::Schema schema = material_schema("leaflet.material");
  const io::Config config = io::Config::validate(
      toml::parse(std::string_view{toml_text}, std::string_view{"case.toml"}), "case.toml", schema);
  return read_material(config, "leaflet.material");
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

} // namespace
} // namespace ibvalve::materials
