// The static grid hierarchy (fluid/hierarchy.hpp): boxes from the case file or placed around the structure,
// and one InputError line "case.toml:line: key: message" for each broken rule.
#include <string>

#include <gtest/gtest.h>

#include "base/errors.hpp"
#include "fluid/hierarchy.hpp"
#include "io/key_binder.hpp"

namespace ibvalve::fluid {
namespace {

// About the study's box (8 x 8 x 14 cm): 8 x 8 x 14.4 cm, level 0 with 20 x 20 x 36 cells (h = 0.4 cm).
BoxGeometry study_box()
{
  BoxGeometry box;
  box.lower = {-4.0, -4.0, -7.2};
  box.upper = {4.0, 4.0, 7.2};
  box.cells = {20, 20, 36};
  box.periodic = {false, false, false};
  return box;
}

const PhysicalBox valve{{-1.4, -1.4, -1.0}, {1.4, 1.4, 1.2}};

GridHierarchy read(const std::string& text, std::optional<PhysicalBox> structure = std::nullopt)
{
  io::Schema schema;
  io::KeyBinder declaring(schema);
  NestedKeys unused;
  bind(declaring, unused);
  const io::Config config = io::Config::validate(
      toml::parse(std::string_view{text}, std::string_view{"case.toml"}), "case.toml", schema);
  io::KeyBinder keys(config);
  NestedKeys k;
  bind(keys, k);
  return read_hierarchy(keys, k, study_box(), structure, "leaflets.mesh");
}

std::string error_of(const std::string& text, std::optional<PhysicalBox> structure = std::nullopt)
{
  try {
    read(text, structure);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(GridHierarchy, WithoutNestedKeysThereIsOneLevelCoveringTheBox)
{
  const GridHierarchy h = read("");
  ASSERT_EQ(h.levels(), 1);
  EXPECT_EQ(h.uncovered_cells(0), 20 * 20 * 36);
}

TEST(GridHierarchy, ExplicitBoxesBecomeCellsOfTheirLevel)
{
  const GridHierarchy h =
      read("[nested]\nratios = [4, 2]\n"
           "[[nested.box]]\nlevel = 1\nlower = [-2.0, -2.0, -2.0]\nupper = [2.0, 2.0, 2.0]\n"
           "[[nested.box]]\nlevel = 2\nlower = [-1.5, -1.5, -1.5]\nupper = [1.5, 1.5, 1.5]\n");
  ASSERT_EQ(h.levels(), 3);
  EXPECT_DOUBLE_EQ(h.h(1, 0), 0.1);
  EXPECT_DOUBLE_EQ(h.h(2, 2), 0.05);
  ASSERT_EQ(h.boxes(1).size(), 1u);
  EXPECT_EQ(h.boxes(1)[0], (IndexBox{{20, 20, 52}, {60, 60, 92}}));
  EXPECT_EQ(h.boxes(2)[0], (IndexBox{{50, 50, 114}, {110, 110, 174}}));
  // Composite cells: level 0 minus the 10^3 cells under level 1, level 1 minus the 30^3 / 8 under level 2.
  EXPECT_EQ(h.uncovered_cells(0), 20 * 20 * 36 - 10 * 10 * 10);
  EXPECT_EQ(h.uncovered_cells(1), 40 * 40 * 40 - 30 * 30 * 30);
  EXPECT_EQ(h.uncovered_cells(2), 60 * 60 * 60);
  EXPECT_TRUE(h.covered(0, {10, 10, 17}));
  EXPECT_FALSE(h.covered(0, {4, 10, 17}));
}

TEST(GridHierarchy, AutomaticPlacementHoldsTheStructureWithItsMarginAlignedAndNested)
{
  const GridHierarchy h = read("[nested]\nratios = [2, 2]\nmargins = [3]\n", valve);
  ASSERT_EQ(h.levels(), 3);
  for (int l = 1; l < 3; ++l) {
    ASSERT_EQ(h.boxes(l).size(), 1u);
    const IndexBox& b = h.boxes(l)[0];
    EXPECT_EQ(b.aligned_outward(h.ratio(l)), b) << "level " << l;
    const IndexBox structure = h.cells_overlapping(l, valve.lower, valve.upper);
    EXPECT_TRUE(b.contains(structure.grown(3))) << "level " << l;
  }
  // Level 1 keeps 3 of its own cells around level 2 (coarsened).
  EXPECT_TRUE(h.boxes(1)[0].contains(h.boxes(2)[0].coarsened(2).grown(3)));
}

TEST(GridHierarchy, EachBrokenRuleIsOneLineNamingTheKey)
{
  const std::string two = "[nested]\nratios = [2]\n";
  // A ratio that is neither 2 nor 4.
  EXPECT_EQ(error_of("[nested]\nratios = [3]\n", valve),
            "case.toml:2: nested.ratios: each ratio must be 2 or 4, got 3");
  // A box of a level that does not exist.
  EXPECT_NE(error_of(two + "[[nested.box]]\nlevel = 2\nlower = [0.0, 0.0, 0.0]\nupper = [0.8, 0.8, 0.8]\n")
                .find("case.toml:4: nested.box[0].level: there are 1 finer levels"),
            std::string::npos);
  // A corner between coarse cell corners (h0 = 0.4 cm).
  EXPECT_NE(error_of(two + "[[nested.box]]\nlevel = 1\nlower = [0.1, 0.0, 0.0]\nupper = [0.8, 0.8, 0.8]\n")
                .find("case.toml:5: nested.box[0].lower: not on a corner of the level-0 cells"),
            std::string::npos);
  // Outside the domain.
  EXPECT_NE(error_of(two + "[[nested.box]]\nlevel = 1\nlower = [0.0, 0.0, 0.0]\nupper = [4.4, 0.8, 0.8]\n")
                .find("case.toml:6: nested.box[0].upper: outside the domain in direction x"),
            std::string::npos);
  // Upper below lower.
  EXPECT_NE(error_of(two + "[[nested.box]]\nlevel = 1\nlower = [0.0, 0.8, 0.0]\nupper = [0.8, 0.0, 0.8]\n")
                .find("nested.box[0].upper: must lie above lower in direction y"),
            std::string::npos);
  // Overlapping boxes of one level.
  EXPECT_NE(error_of(two + "[[nested.box]]\nlevel = 1\nlower = [0.0, 0.0, 0.0]\nupper = [1.6, 1.6, 1.6]\n"
                           "[[nested.box]]\nlevel = 1\nlower = [0.8, 0.8, 0.8]\nupper = [2.4, 2.4, 2.4]\n")
                .find("case.toml:9: nested.box[1].lower: the box overlaps box 0 of level 1"),
            std::string::npos);
  // Level 2 touching the edge of level 1: not properly nested.
  EXPECT_NE(error_of("[nested]\nratios = [2, 2]\n"
                     "[[nested.box]]\nlevel = 1\nlower = [-2.0, -2.0, -2.0]\nupper = [2.0, 2.0, 2.0]\n"
                     "[[nested.box]]\nlevel = 2\nlower = [-2.0, -1.0, -1.0]\nupper = [1.0, 1.0, 1.0]\n")
                .find("case.toml:9: nested.box[1].lower: the box cells [20,50)x[30,50)x["),
            std::string::npos);
  // The structure outside an explicit finest level names the structure's key.
  EXPECT_NE(error_of(two + "[[nested.box]]\nlevel = 1\nlower = [-0.8, -0.8, -0.8]\nupper = [0.8, 0.8, 0.8]\n",
                     valve)
                .find("leaflets.mesh: the structure (bounding box with 2 cells of kernel reach"),
            std::string::npos);
  // No boxes and no structure to place them around.
  EXPECT_NE(error_of(two).find("nested.box: level 1 has no [[nested.box]] and there is no structure"),
            std::string::npos);
  // A margin list of the wrong length.
  EXPECT_NE(error_of("[nested]\nratios = [2, 2]\nmargins = [2, 2, 2]\n", valve)
                .find("case.toml:3: nested.margins: give one margin or one per finer level (2), got 3"),
            std::string::npos);
  // Ranges the schema checks: a ratio above 4.
  EXPECT_NE(error_of("[nested]\nratios = [8]\n").find("nested.ratios"), std::string::npos);
}

TEST(GridHierarchy, ConstructorRejectsMisalignedAndImproperlyNestedBoxes)
{
  BoxGeometry box;
  box.cells = {8, 8, 8};
  EXPECT_THROW(GridHierarchy(box, {FinerLevel{2, {IndexBox{{1, 2, 2}, {6, 6, 6}}}}}), HierarchyError);
  EXPECT_NO_THROW(GridHierarchy(box, {FinerLevel{2, {IndexBox{{2, 2, 2}, {6, 6, 6}}}}}));
  // Level 2 inside level 1 but touching its edge (no level-1 cell to spare).
  try {
    GridHierarchy(box, {FinerLevel{2, {IndexBox{{4, 4, 4}, {12, 12, 12}}}},
                        FinerLevel{2, {IndexBox{{8, 8, 8}, {16, 16, 16}}}}});
    FAIL() << "accepted an improperly nested level";
  } catch (const HierarchyError& e) {
    EXPECT_EQ(e.level(), 2);
    EXPECT_EQ(e.box(), 0);
  }
  EXPECT_NO_THROW(GridHierarchy(box, {FinerLevel{2, {IndexBox{{4, 4, 4}, {12, 12, 12}}}},
                                      FinerLevel{2, {IndexBox{{10, 10, 10}, {14, 14, 14}}}}}));
}

} // namespace
} // namespace ibvalve::fluid
