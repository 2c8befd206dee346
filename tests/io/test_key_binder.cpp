// Keys bound once (io/key_binder.hpp): the same bind declares a schema and reads a validated case; a table
// list's elements are bound in place by an element bind, and a message about an element's key names the
// element ("pump.stage[1].name") at the line the case gives it.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "base/errors.hpp"
#include "base/units.hpp"
#include "io/key_binder.hpp"

namespace ibvalve::io {
namespace {

struct Stage {
  std::string name;
  double head = 0.0;
  std::vector<std::pair<std::string, double>> gains;
};

struct Pump {
  std::string label;
  std::vector<Stage> stages;
};

void bind(KeyBinder& keys, Stage& s)
{
  keys.string("name", "the stage's name", s.name).required();
  keys.real("head", "pressure head", s.head).unit("mmHg").defaults(10.0).non_negative();
  keys.named_reals("gains", "named gains, as written", s.gains);
}

void bind(KeyBinder& keys, Pump& p)
{
  keys.string("pump.label", "a label without a default", p.label);
  keys.tables("pump.stage", "the pump's stages", p.stages,
              [](KeyBinder& element, Stage& s) { bind(element, s); });
}

Schema pump_schema()
{
  Schema schema;
  KeyBinder declaring(schema);
  Pump unused;
  bind(declaring, unused);
  return schema;
}

Config pump_case(const std::string& text)
{
  return Config::validate(toml::parse(std::string_view{text}, std::string_view{"case.toml"}), "case.toml",
                          pump_schema());
}

TEST(KeyBinder, ATableListsElementsDeclareTheElementsSchema)
{
  const Schema schema = pump_schema();
  const KeySpec* stage = schema.find("pump.stage");
  ASSERT_NE(stage, nullptr);
  EXPECT_EQ(stage->kind, ValueKind::table_list);
  ASSERT_NE(stage->element, nullptr);
  const KeySpec* head = stage->element->find("head");
  ASSERT_NE(head, nullptr);
  EXPECT_EQ(head->unit, "mmHg");
  EXPECT_TRUE(stage->element->find("name")->required);
  EXPECT_EQ(stage->element->find("gains")->kind, ValueKind::real_table);
}

TEST(KeyBinder, ReadsEachElementInPlaceAndNamesItsKeysInMessages)
{
  const Config config = pump_case("[[pump.stage]]\nname = \"first\"\n\n[[pump.stage]]\nname = \"second\"\n"
                                  "head = 2.0\ngains = { a = 1.5, b = 3 }\n");
  KeyBinder keys(config);
  Pump p;
  bind(keys, p);
  ASSERT_EQ(p.stages.size(), 2u);
  EXPECT_EQ(p.stages[0].name, "first");
  EXPECT_DOUBLE_EQ(p.stages[0].head, 10.0 * units::mmHg); // the default, in CGS
  EXPECT_TRUE(p.stages[0].gains.empty());
  EXPECT_EQ(p.stages[1].gains, (std::vector<std::pair<std::string, double>>{{"a", 1.5}, {"b", 3.0}}));
  // Within its element a key is named as the element names it; a message names the element too.
  EXPECT_EQ(keys.key_of(p.stages[1].head), "head");
  EXPECT_TRUE(keys.has(p.stages[0].head)); // its default
  EXPECT_TRUE(keys.has(p.stages[1].name));
  EXPECT_TRUE(keys.has(p.stages[1].gains));
  EXPECT_FALSE(keys.has(p.stages[0].gains)); // no default, not given
  EXPECT_FALSE(keys.has(p.label));
  EXPECT_EQ(&keys.config_of(p.label), &config);
  try {
    keys.fail(p.stages[1].head, "too high");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "case.toml:6: pump.stage[1].head: too high");
  }
  try {
    keys.fail(p.stages, "needs three stages");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "case.toml:1: pump.stage: needs three stages");
  }
}

TEST(KeyBinder, ATableListNotGivenLeavesTheTargetEmpty)
{
  const Config config = pump_case("pump.label = \"p\"\n");
  KeyBinder keys(config);
  Pump p;
  p.stages.resize(3);
  bind(keys, p);
  EXPECT_TRUE(p.stages.empty());
  EXPECT_EQ(p.label, "p");
  EXPECT_TRUE(keys.has(p.label));
}

} // namespace
} // namespace ibvalve::io
