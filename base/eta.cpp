#include "base/eta.hpp"

#include <algorithm>

namespace ibvalve::base {

void EtaEstimator::begin(long step, double wall)
{
  first_step_ = step;
  samples_.assign(1, {step, wall});
}

void EtaEstimator::record(long step, double wall)
{
  if (!samples_.empty() && step <= samples_.back().first) return;
  samples_.emplace_back(step, wall);
  // The invocation's first step goes once a later one is measured (its set-up is no step's pace).
  if (samples_.size() > 2 && samples_.front().first == first_step_ && samples_[1].first == first_step_ + 1)
    samples_.pop_front();
  // Keep the window: drop the oldest sample while the one after it still starts `window_` back.
  while (samples_.size() > 2 && wall - samples_[1].second >= window_) samples_.pop_front();
}

double EtaEstimator::step_seconds() const
{
  if (samples_.size() < 2) return -1.0;
  const auto& [oldest_step, oldest_wall] = samples_.front();
  const auto& [newest_step, newest_wall] = samples_.back();
  return (newest_wall - oldest_wall) / static_cast<double>(newest_step - oldest_step);
}

double EtaEstimator::seconds_left(long last_step) const
{
  const double pace = step_seconds();
  if (pace < 0.0) return -1.0;
  return static_cast<double>(std::max(0L, last_step - samples_.back().first)) * pace;
}

} // namespace ibvalve::base
