#include "app/step_schedule.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace ibvalve::app {

std::string step_count_problem(double length, double step)
{
  const double steps = length / step;
  if (std::isfinite(steps) && steps <= max_run_steps) return "";
  const std::string count =
      std::isfinite(steps) ? fmt::format("{:.3g} steps", steps) : "more steps than a double counts";
  return fmt::format("{} s over {} s is {}, more than the {:.0e} a run takes at most (a time step in another "
                     "unit?)",
                     step, length, count, max_run_steps);
}

namespace {
std::int64_t whole_steps(double length, double step)
{
  return length > 0.0 ? std::max<std::int64_t>(1, std::llround(length / step)) : 0;
}
} // namespace

StepSchedule::StepSchedule(double period, double step) : period_(period)
{
  if (!(period > 0.0) || !(step > 0.0))
    throw std::invalid_argument("StepSchedule: period and step must be positive");
  counts_ = {whole_steps(period, step), 0, 0};
  starts_ = {0.0, period, period};
  steps_ = {period / static_cast<double>(counts_[0]), 0.0, 0.0};
}

StepSchedule::StepSchedule(double period, double step, double fine_step, std::array<double, 2> window)
    : period_(period)
{
  const auto [a, b] = window;
  if (!(period > 0.0) || !(step > 0.0) || !(fine_step > 0.0))
    throw std::invalid_argument("StepSchedule: period and steps must be positive");
  if (!(a >= 0.0 && a < b && b <= period))
    throw std::invalid_argument("StepSchedule: the window must lie in the cycle, start before its end");
  counts_ = {whole_steps(a, step), whole_steps(b - a, fine_step), whole_steps(period - b, step)};
  starts_ = {0.0, a, b};
  const std::array<double, 3> lengths{a, b - a, period - b};
  for (int p = 0; p < 3; ++p) steps_[p] = counts_[p] > 0 ? lengths[p] / static_cast<double>(counts_[p]) : 0.0;
}

double StepSchedule::time_in_cycle(std::int64_t m) const
{
  for (int p = 0; p < 3; ++p) {
    if (m <= counts_[p]) return starts_[p] + static_cast<double>(m) * steps_[p];
    m -= counts_[p];
  }
  return period_;
}

double StepSchedule::time_of(std::int64_t n) const
{
  const std::int64_t per = steps_per_cycle();
  return static_cast<double>(n / per) * period_ + time_in_cycle(n % per);
}

double StepSchedule::step(std::int64_t n) const
{
  std::int64_t m = (n - 1) % steps_per_cycle(); // steps of this cycle before step n
  for (int p = 0; p < 3; ++p) {
    if (m < counts_[p]) return steps_[p];
    m -= counts_[p];
  }
  return steps_[2];
}

std::int64_t StepSchedule::steps_to(double t) const
{
  if (uniform()) return std::llround(t / steps_[0]);
  const std::int64_t per = steps_per_cycle();
  const auto cycles = static_cast<std::int64_t>(std::floor(t / period_));
  double rest = t - static_cast<double>(cycles) * period_;
  std::int64_t n = cycles * per;
  for (int p = 0; p < 3; ++p) {
    const double length = static_cast<double>(counts_[p]) * steps_[p];
    if (counts_[p] > 0 && rest <= length) return n + std::llround(rest / steps_[p]);
    rest -= length;
    n += counts_[p];
  }
  return n;
}

} // namespace ibvalve::app
