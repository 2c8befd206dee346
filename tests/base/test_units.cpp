// Units at the edges: every conversion the case files use, against the definitions in docs/reference.md,
// "Units".
#include <gtest/gtest.h>

#include "base/units.hpp"

namespace ibvalve::units {
namespace {

TEST(Units, PressureConversionsFollowTheReference)
{
  EXPECT_DOUBLE_EQ(*to_cgs("mmHg"), 1333.22);
  EXPECT_DOUBLE_EQ(*to_cgs("kPa"), 1.0e4);
  EXPECT_DOUBLE_EQ(*to_cgs("Pa"), 10.0);
}

TEST(Units, LumpedParametersConvertConsistently)
{
  // R in mmHg s/mL times C in mL/mmHg is a time in seconds, in any units.
  EXPECT_DOUBLE_EQ(*to_cgs("mmHg s/mL") * *to_cgs("mL/mmHg"), 1.0);
  EXPECT_DOUBLE_EQ(*to_cgs("cP"), 0.01);
  EXPECT_DOUBLE_EQ(*to_cgs("mm"), 0.1);
}

TEST(Units, UnknownUnitIsRefused)
{
  EXPECT_FALSE(to_cgs("furlong").has_value());
}

} // namespace
} // namespace ibvalve::units
