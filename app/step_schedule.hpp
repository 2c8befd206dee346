#pragma once
// The time steps of a periodic run: one step through the cycle, or a finer one over a window of each
// cycle (the leaflets' coaptation, where the explicit IB/FE coupling needs it: docs/runs.md, "A finer
// step over the coaptation").
// The cycle is cut into [0, a), [a, b) and [b, T); each part holds a whole number of equal steps, the
// nearest to the asked step, so every cycle starts and ends on a step and the window's ends are met
// exactly.
#include <array>
#include <cstdint>
#include <string>

namespace ibvalve::app {

/// The most steps one run takes: a billion steps of the cheapest model (the lumped one, microseconds a
/// step) is an hour, of a grid model years. More is a time step given in the wrong unit or exponent,
/// and a count beyond it would also overflow where steps are counted and rounded (docs/runs.md).
inline constexpr double max_run_steps = 1e9;

/// Why `length` s in steps of `step` s cannot be run ("" when they can): more steps than
/// max_run_steps, or a step so small against the length that their quotient is no finite number.
std::string step_count_problem(double length, double step);

class StepSchedule {
 public:
  /// `step` through the whole cycle of length `period`.
  StepSchedule(double period, double step);
  /// `step`, and `fine_step` over [window[0], window[1]) of each cycle (0 <= window[0] < window[1] <=
  /// period; std::invalid_argument otherwise).
  StepSchedule(double period, double step, double fine_step, std::array<double, 2> window);

  std::int64_t steps_per_cycle() const { return counts_[0] + counts_[1] + counts_[2]; }
  /// The length of step n (1, 2, ...): from time_of(n - 1) to time_of(n).
  double step(std::int64_t n) const;
  /// The time after n steps from the start.
  double time_of(std::int64_t n) const;
  /// The number of steps whose end is nearest to `t` (t >= 0).
  std::int64_t steps_to(double t) const;
  /// The cycle's length over its steps: steps x mean_step is the end time of whole cycles.
  double mean_step() const { return period_ / static_cast<double>(steps_per_cycle()); }
  bool uniform() const { return counts_[1] == 0; }

 private:
  double period_;
  std::array<double, 3> starts_{}, steps_{}; // each part's start in the cycle and its step
  std::array<std::int64_t, 3> counts_{};     // steps in each part
  /// The time within a cycle after m of its steps (0 <= m <= steps_per_cycle()).
  double time_in_cycle(std::int64_t m) const;
};

} // namespace ibvalve::app
