// The adaptive step's choice (app/adaptive_step.hpp): the fewest equal sub-steps of an interval within
// the longest step, the structure's estimate times the safety factor and the fluid's CFL limit; more
// at once when the state asks, fewer only once the allowed step has grown by the set factor.
#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>
#include <vector>

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

TEST(AdaptiveStep, ALimitMovingTheWrongWayIsCarriedToTheIntervalsEnd)
{
  using ibvalve::app::extrapolated_limits;
  using ibvalve::app::StepLimits;
  // The closure with the tube as a wall: the estimate 1.32e-4 s, a third lower than the interval
  // before's: taken at 1.32e-4 * (1.32 / 1.6) = 1.089e-4 s.
  const StepLimits falling = extrapolated_limits({1.32e-4, 0.0}, {1.6e-4, 0.0});
  EXPECT_DOUBLE_EQ(falling.structure_dt, 1.32e-4 * (1.32e-4 / 1.6e-4));
  // The jet as the valve opens: max|u| / h up 1.5 times since the interval before: 1.5 times again.
  const StepLimits speeding = extrapolated_limits({1e-3, 3e3}, {1e-3, 2e3});
  EXPECT_DOUBLE_EQ(speeding.speed_over_h, 4.5e3);
  EXPECT_DOUBLE_EQ(speeding.structure_dt, 1e-3);
  // A limit moving the safe way, or none known before (the run's start, an old checkpoint), as it is.
  const StepLimits easing = extrapolated_limits({2e-4, 1e3}, {1e-4, 2e3});
  EXPECT_DOUBLE_EQ(easing.structure_dt, 2e-4);
  EXPECT_DOUBLE_EQ(easing.speed_over_h, 1e3);
  const StepLimits first = extrapolated_limits({1e-4, 1e3}, {});
  EXPECT_DOUBLE_EQ(first.structure_dt, 1e-4);
  EXPECT_DOUBLE_EQ(first.speed_over_h, 1e3);
  // What the choice then gives, at the next interval of that closure (9.03e-5 s after 1.32e-4): 0.9 x
  // 6.18e-5 s over 1.6 ms is 29 sub-steps, where the estimate as it was gave 20.
  const AdaptiveStep a = chooser();
  const StepLimits next = extrapolated_limits({9.03e-5, 0.0}, {1.32e-4, 0.0});
  EXPECT_EQ(a.substeps(1.6e-3, 9.03e-5, 0.0, 0), 20);
  EXPECT_EQ(a.substeps(1.6e-3, next.structure_dt, 0.0, 0), 29);
}

TEST(AdaptiveStep, AfterAnIntervalTakenAgainTheStepThatWentThroughCapsTheNextOnesUntilItHasGrownBack)
{
  const AdaptiveStep a = chooser();
  // W1FD1 on the 1/16 cm grid as its valve opens (docs/runs.md): 44 sub-steps of an 0.8 ms interval blew
  // up, 88 went through (9.09e-6 s), and the next interval's estimate allows 0.9 x 2.73e-5 s again.
  const double went_through = 0.8e-3 / 88.0;
  double cap = a.relaxed_cap(went_through);
  EXPECT_DOUBLE_EQ(cap, 1.2 * went_through);
  EXPECT_DOUBLE_EQ(a.allowed_step(2.73e-5, 0.0, cap), cap);
  // m falls from 88 by the factor 1.2 an interval (74, 62, 51, 43, 36), not at once to 33; then the
  // estimate binds, and 33 would lengthen the step by less than 1.2: 36 stay.
  std::int64_t m = 88;
  std::vector<std::int64_t> counts;
  for (int interval = 0; interval < 6; ++interval) {
    m = a.substeps(0.8e-3, 2.73e-5, 0.0, m, cap);
    counts.push_back(m);
    cap = a.relaxed_cap(cap);
  }
  EXPECT_EQ(counts, (std::vector<std::int64_t>{74, 62, 51, 43, 36, 36}));
  // The cap is gone once it has grown past the longest step; none (0) stays none.
  EXPECT_EQ(a.relaxed_cap(0.9e-4), 0.0);
  EXPECT_EQ(a.relaxed_cap(0.0), 0.0);
  EXPECT_DOUBLE_EQ(a.allowed_step(2.73e-5, 0.0, 0.0), 0.9 * 2.73e-5);
}

TEST(AdaptiveStep, BadSettingsAndStatesAreRefused)
{
  EXPECT_THROW(AdaptiveStep(AdaptiveStepSettings{0.0, 1e-4, 0.9, 0.5, 1.2}), std::invalid_argument);
  EXPECT_THROW(AdaptiveStep(AdaptiveStepSettings{1e-3, 1e-4, 0.9, 0.5, 0.9}), std::invalid_argument);
  const AdaptiveStep a = chooser();
  EXPECT_THROW((void)a.allowed_step(0.0, 0.0), std::runtime_error);
  EXPECT_THROW((void)a.allowed_step(1.0, std::numeric_limits<double>::infinity()), std::runtime_error);
}
