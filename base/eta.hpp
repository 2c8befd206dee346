#pragma once
// The progress line's ETA (base/logger.hpp): the steps left times the wall time a step over a recent
// window, not since the run began. The mean since the start misleads twice: the first step carries
// set-up (the first solves' factorisations, the coupled stability estimate) and a shared machine's
// load, a cycle's phases and an adaptive step change what a step costs as the run goes on (a default
// valve run's first line said 6:14:01, and mid-run the mean-based ETA was 30-44 % off).
#include <deque>
#include <utility>

namespace ibvalve::base {

class EtaEstimator {
 public:
  /// `window`: the wall seconds of recent steps the pace is measured over (at least the last step).
  explicit EtaEstimator(double window = 300.0) : window_(window) {}

  /// This invocation's steps start after `step`, at wall time `wall` (s).
  void begin(long step, double wall);
  /// Step `step` ended at wall time `wall` (s). Steps may be recorded in strides (every 1000th).
  void record(long step, double wall);
  /// Wall seconds a step over the window: from the oldest kept sample to the newest, leaving out the
  /// invocation's first step once a later one is measured. Negative before a step was measured.
  double step_seconds() const;
  /// Wall seconds left to `last_step` from the newest recorded step; negative while unknown.
  double seconds_left(long last_step) const;

 private:
  double window_;
  long first_step_ = 0;
  std::deque<std::pair<long, double>> samples_; // (step, wall), oldest first
};

} // namespace ibvalve::base
