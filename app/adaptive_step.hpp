#pragma once
// An adaptive step for the explicit IB/FE coupling (docs/runs.md, "The adaptive step"). The run's
// loop steps through fixed intervals (its rows, snapshots, checkpoints and cycle ends fall on them);
// each interval is taken in m equal sub-steps, m chosen at its start from the state there:
//
//   dt_allowed = min(largest, safety x dt_structure, cfl x h / max|u|),   m >= interval / dt_allowed,
//
// dt_structure the structure's stability estimate at its current deformation (ib/ibfe.hpp: the
// exponential fiber laws stiffen as the leaflets load, so the limit moves through the cycle) and the
// last term the fluid's advective limit. A changed step costs the fluid a new operator (its set-up),
// so m falls only when the allowed step has grown by `grow` or more; it rises at once.
#include <cstdint>

namespace ibvalve::app {

struct AdaptiveStepSettings {
  double interval = 1e-3;               ///< s: the loop's step
  double largest = 1e-4;                ///< s: no sub-step longer
  double safety = 0.9;                  ///< the fraction of the structure's estimate a sub-step may take
  double cfl = 0.5;                     ///< the largest advective CFL number max|u| dt / h
  double grow = 1.2;                    ///< the factor the allowed step must grow by before m falls
  std::int64_t estimate_iterations = 6; ///< power iterations of the structure's estimate an interval
};

class AdaptiveStep {
 public:
  explicit AdaptiveStep(const AdaptiveStepSettings& settings);

  /// The sub-steps of the next interval of length `interval` (s), from the structure's estimate
  /// `structure_dt` (s) and the fluid's largest speed over its smallest spacing `speed_over_h` (1/s),
  /// given `previous` sub-steps over the interval before (0 at the run's start).
  std::int64_t substeps(double interval, double structure_dt, double speed_over_h,
                        std::int64_t previous) const;
  /// The step the state allows: min(largest, safety x structure_dt, cfl / speed_over_h).
  double allowed_step(double structure_dt, double speed_over_h) const;
  const AdaptiveStepSettings& settings() const { return settings_; }

 private:
  AdaptiveStepSettings settings_;
};

} // namespace ibvalve::app
