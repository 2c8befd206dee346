// The choice of how a part's volumetric penalty is integrated (fe/volumetric_integration.hpp): its key
// structure.volumetric_integration, declared and read by one bind with the model's default, and the body
// part it makes of a Material: whole on the Gauss rule ("full"), or its law there and its penalty on the
// element's centre rule ("reduced"), a Material without a penalty whole either way.
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "base/errors.hpp"
#include "fe/volumetric_integration.hpp"
#include "materials/law.hpp"

namespace ibvalve::fe {
namespace {

/// The integration a case reads, with `default_value` the model's.
VolumetricIntegration read(const std::string& text, VolumetricIntegration default_value)
{
  io::Schema schema;
  {
    io::KeyBinder declaring(schema);
    VolumetricIntegration unused{};
    bind(declaring, unused, default_value);
  }
  const io::Config config = io::Config::validate(
      toml::parse(std::string_view{text}, std::string_view{"case.toml"}), "case.toml", schema);
  io::KeyBinder keys(config);
  VolumetricIntegration integration = default_value == VolumetricIntegration::full
                                          ? VolumetricIntegration::reduced
                                          : VolumetricIntegration::full;
  bind(keys, integration, default_value);
  return integration;
}

TEST(VolumetricIntegration, TheKeyReadsTheCasesChoiceOrTheModelsDefault)
{
  EXPECT_EQ(read("", VolumetricIntegration::reduced), VolumetricIntegration::reduced);
  EXPECT_EQ(read("", VolumetricIntegration::full), VolumetricIntegration::full);
  EXPECT_EQ(read("[structure]\nvolumetric_integration = \"full\"\n", VolumetricIntegration::reduced),
            VolumetricIntegration::full);
  EXPECT_EQ(read("[structure]\nvolumetric_integration = \"reduced\"\n", VolumetricIntegration::full),
            VolumetricIntegration::reduced);
  EXPECT_THROW(read("[structure]\nvolumetric_integration = \"half\"\n", VolumetricIntegration::full),
               InputError);
}

std::shared_ptr<const materials::Material> neo_hookean(materials::PenaltyKind penalty)
{
  auto law =
      std::make_shared<materials::InvariantLaw>(materials::LawKind::neo_hookean, std::vector<double>{1e4});
  return std::make_shared<materials::Material>(law, materials::VolumetricPenalty(penalty, 1e7));
}

TEST(VolumetricIntegration, ReducedPutsThePenaltyOnTheCentreRuleAndFullKeepsTheMaterialWhole)
{
  const auto material = neo_hookean(materials::PenaltyKind::log);
  const BodyPart full = material_part("p", {0, 1}, material, VolumetricIntegration::full);
  ASSERT_EQ(full.laws.size(), 1u);
  EXPECT_EQ(full.laws[0].get(), material.get());
  EXPECT_TRUE(full.centre_laws.empty());
  EXPECT_EQ(full.elements, (std::vector<int>{0, 1}));

  const BodyPart reduced = material_part("p", {0, 1}, material, VolumetricIntegration::reduced);
  ASSERT_EQ(reduced.laws.size(), 1u);
  ASSERT_EQ(reduced.centre_laws.size(), 1u);
  EXPECT_EQ(reduced.laws[0].get(), &material->law());
  EXPECT_EQ(reduced.centre_laws[0].get(), &material->penalty());

  const auto without_penalty = neo_hookean(materials::PenaltyKind::none);
  const BodyPart whole = material_part("p", {0}, without_penalty, VolumetricIntegration::reduced);
  ASSERT_EQ(whole.laws.size(), 1u);
  EXPECT_EQ(whole.laws[0].get(), without_penalty.get());
  EXPECT_TRUE(whole.centre_laws.empty());
}

} // namespace
} // namespace ibvalve::fe
