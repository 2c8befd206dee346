#pragma once
// An adaptive step for the explicit IB/FE coupling (docs/runs.md, "The adaptive step"). The run's
// loop steps through fixed intervals (its rows, snapshots, checkpoints and cycle ends fall on them);
// each interval is taken in m equal sub-steps, m chosen at its start from the state there:
//
//   dt_allowed = min(largest, safety x dt_structure, cfl x h / max|u|),   m >= interval / dt_allowed,
//
// dt_structure the structure's stability estimate at its current deformation (ib/ibfe.hpp: the
// exponential fiber laws stiffen as the leaflets load, so the limit moves through the cycle) and the
// last term the fluid's advective limit. Both are taken at the interval's start, but the step holds to
// its end: a limit that moved the wrong way since the interval before is extrapolated by that change
// (extrapolated_limits), so a closure whose estimate falls by a third an interval is met where it will
// be, not where it was. m falls only when the allowed step has grown by `grow` or more (fewer changes of
// the Adams-Bashforth ratio); it rises at once. An estimate at the interval's start cannot see a fold that
// forms within the interval (docs/runs.md): an interval whose sub-steps go unstable (a point leaves the
// grid, a solver diverges, the flow is not finite) is taken again from its start with twice the
// sub-steps, up to `retries` times, before the run stops. The estimate missed the limit there and may
// miss it in the intervals that follow: the sub-step that went through caps the next intervals' steps,
// the cap growing by `grow` an interval until the estimate binds again (relaxed_cap).
#include <cstdint>

namespace ibvalve::app {

struct AdaptiveStepSettings {
  double interval = 1e-3;               ///< s: the loop's step
  double largest = 1e-4;                ///< s: no sub-step longer
  double safety = 0.9;                  ///< the fraction of the structure's estimate a sub-step may take
  double cfl = 0.5;                     ///< the largest advective CFL number max|u| dt / h
  double grow = 1.2;                    ///< the factor the allowed step must grow by before m falls
  std::int64_t estimate_iterations = 6; ///< power iterations of the structure's estimate an interval
  std::int64_t retries = 3;             ///< times a failed interval is taken again with twice the sub-steps
};

/// The two state-dependent limits at an interval's start.
struct StepLimits {
  double structure_dt = 0.0; ///< s: the structure's stability estimate
  double speed_over_h = 0.0; ///< 1/s: the fluid's largest speed over its smallest spacing
};

/// The limits `now` carried to the interval's end by their change since `before` (the last interval's
/// start; a zero there: none known): a falling structure estimate is multiplied by now/before, a rising
/// speed likewise; a limit moving the safe way is taken as it is (one interval's change, no more, so
/// that a quiet state does not pay).
StepLimits extrapolated_limits(const StepLimits& now, const StepLimits& before);

class AdaptiveStep {
 public:
  explicit AdaptiveStep(const AdaptiveStepSettings& settings);

  /// The sub-steps of the next interval of length `interval` (s), from the structure's estimate
  /// `structure_dt` (s) and the fluid's largest speed over its smallest spacing `speed_over_h` (1/s),
  /// given `previous` sub-steps over the interval before (0 at the run's start).
  std::int64_t substeps(double interval, double structure_dt, double speed_over_h, std::int64_t previous,
                        double cap = 0.0) const;
  /// The step the state allows: min(largest, safety x structure_dt, cfl / speed_over_h, cap); a cap of 0
  /// is none.
  double allowed_step(double structure_dt, double speed_over_h, double cap = 0.0) const;
  /// The cap one interval later: `grow` times longer, none (0) once no shorter than the largest step.
  double relaxed_cap(double cap) const;
  const AdaptiveStepSettings& settings() const { return settings_; }

 private:
  AdaptiveStepSettings settings_;
};

} // namespace ibvalve::app
