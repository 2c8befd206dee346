// The adaptive step's choice (app/adaptive_step.hpp): the fewest equal sub-steps of an interval within
// the longest step, the structure's estimate times the safety factor and the fluid's CFL limit; more
// at once when the state asks, fewer only once the allowed step has grown by the set factor.
#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>

#include "app/adaptive_step.hpp"

using ibvalve::app::AdaptiveStep;
using ibvalve::app::AdaptiveStepSettings;

namespace {
// Intervals of 1.6 ms, sub-steps up to 1e-4 s, 0.9 of the structure's estimate, CFL 0.5, grow 1.2.
AdaptiveStep chooser()
{
  return AdaptiveStep(AdaptiveStepSettings{1.6e-3, 1e-4, 0.9, 0.5, 1.2});
}
} // namespace

TEST(AdaptiveStep, TheSmallestLimitSetsTheStep)
{
  const AdaptiveStep a = chooser();
  EXPECT_DOUBLE_EQ(a.allowed_step(1.0, 0.0), 1e-4);        // the longest step
  EXPECT_DOUBLE_EQ(a.allowed_step(5e-5, 0.0), 0.9 * 5e-5); // the structure
  EXPECT_DOUBLE_EQ(a.allowed_step(1.0, 1e4), 0.5 / 1e4);   // the fluid: CFL 0.5 at |u|/h = 1e4 1/s
  EXPECT_DOUBLE_EQ(a.allowed_step(4e-5, 1e4), 0.9 * 4e-5);
}

TEST(AdaptiveStep, AnIntervalTakesTheFewestSubStepsWithinTheAllowedStep)
{
  const AdaptiveStep a = chooser();
  EXPECT_EQ(a.substeps(1.6e-3, 1.0, 0.0, 0), 16);   // 1.6e-3 / 1e-4 exactly: no 17th
  EXPECT_EQ(a.substeps(1.6e-3, 5e-5, 0.0, 0), 36);  // 1.6e-3 / 4.5e-5 = 35.6
  EXPECT_EQ(a.substeps(1.6e-3, 1e-3, 2e5, 0), 640); // CFL: 2.5e-6 s
  EXPECT_EQ(a.substeps(1e-5, 1.0, 0.0, 0), 1);      // a short interval is one step
}

TEST(AdaptiveStep, MoreSubStepsAtOnceFewerOnlyWhenTheStepGrowsEnough)
{
  const AdaptiveStep a = chooser();
  // Stiffening: 36 sub-steps before, the estimate falls: 45 now.
  EXPECT_EQ(a.substeps(1.6e-3, 4e-5, 0.0, 36), 45);
  // Softening a little (4.5e-5 -> 5e-5 allowed, 11 % more): the 36 sub-steps stay, the fluid keeps its
  // operator.
  EXPECT_EQ(a.substeps(1.6e-3, 5.0 / 0.9 * 1e-5, 0.0, 36), 36);
  // Softening by more than the factor 1.2 (4.44e-5 -> 6e-5): 27 sub-steps.
  EXPECT_EQ(a.substeps(1.6e-3, 6e-5 / 0.9, 0.0, 36), 27);
}

TEST(AdaptiveStep, BadSettingsAndStatesAreRefused)
{
  EXPECT_THROW(AdaptiveStep(AdaptiveStepSettings{0.0, 1e-4, 0.9, 0.5, 1.2}), std::invalid_argument);
  EXPECT_THROW(AdaptiveStep(AdaptiveStepSettings{1e-3, 1e-4, 0.9, 0.5, 0.9}), std::invalid_argument);
  const AdaptiveStep a = chooser();
  EXPECT_THROW((void)a.allowed_step(0.0, 0.0), std::runtime_error);
  EXPECT_THROW((void)a.allowed_step(1.0, std::numeric_limits<double>::infinity()), std::runtime_error);
}
