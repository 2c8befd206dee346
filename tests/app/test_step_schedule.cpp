// The time steps of a periodic run (app/step_schedule.hpp): one step through the cycle, as the
// aortic-valve model always had (the same doubles), or a finer one over a window of each cycle whose
// ends are met exactly; every cycle holds a whole number of steps.
#include <cmath>

#include <gtest/gtest.h>

#include "app/step_schedule.hpp"

using ibvalve::app::StepSchedule;

TEST(StepSchedule, OneStepIsThePeriodOverTheNearestWholeNumberOfSteps)
{
  const StepSchedule s(0.8, 3e-5);
  EXPECT_TRUE(s.uniform());
  EXPECT_EQ(s.steps_per_cycle(), 26667);
  const double dt = 0.8 / 26667.0; // what the model computed before the schedule
  EXPECT_EQ(s.step(1), dt);
  EXPECT_EQ(s.step(26667 * 2 + 5), dt);
  EXPECT_EQ(s.mean_step(), dt);
  EXPECT_EQ(s.steps_to(0.5), std::lround(0.5 / dt));
  EXPECT_DOUBLE_EQ(s.time_of(26667), 0.8);
}

TEST(StepSchedule, TheFineWindowEndsOnStepsAndEveryCycleIsWhole)
{
  const StepSchedule s(0.8, 3e-5, 2e-5, {0.37, 0.47});
  EXPECT_FALSE(s.uniform());
  const std::int64_t before = 12333, fine = 5000, after = 11000; // 0.37 / 3e-5, 0.1 / 2e-5, 0.33 / 3e-5
  EXPECT_EQ(s.steps_per_cycle(), before + fine + after);
  EXPECT_DOUBLE_EQ(s.step(1), 0.37 / before);
  EXPECT_DOUBLE_EQ(s.step(before + 1), 0.1 / fine);
  EXPECT_DOUBLE_EQ(s.step(before + fine + 1), 0.33 / after);
  // The window's ends and the cycle's end, in every cycle.
  for (std::int64_t k : {0, 1, 2}) {
    const std::int64_t n0 = k * s.steps_per_cycle();
    EXPECT_NEAR(s.time_of(n0 + before), 0.8 * k + 0.37, 1e-15);
    EXPECT_NEAR(s.time_of(n0 + before + fine), 0.8 * k + 0.47, 1e-15);
    EXPECT_NEAR(s.time_of(n0 + s.steps_per_cycle()), 0.8 * (k + 1), 1e-15);
  }
  // The steps add up to the times.
  double t = 0.0;
  for (std::int64_t n = 1; n <= 2 * s.steps_per_cycle(); ++n) t += s.step(n);
  EXPECT_NEAR(t, 1.6, 1e-11);
  EXPECT_NEAR(s.mean_step() * static_cast<double>(s.steps_per_cycle()), 0.8, 1e-15);
  EXPECT_EQ(s.steps_to(0.37), before);
  EXPECT_EQ(s.steps_to(0.8 + 0.42), s.steps_per_cycle() + before + 2500);
}

TEST(StepSchedule, AWindowOutsideTheCycleIsRefused)
{
  EXPECT_THROW(StepSchedule(0.8, 3e-5, 2e-5, {0.5, 0.4}), std::invalid_argument);
  EXPECT_THROW(StepSchedule(0.8, 3e-5, 2e-5, {0.1, 0.9}), std::invalid_argument);
}
