#include "app/adaptive_step.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ibvalve::app {

AdaptiveStep::AdaptiveStep(const AdaptiveStepSettings& settings) : settings_(settings)
{
  const AdaptiveStepSettings& s = settings_;
  if (!(s.interval > 0.0) || !(s.largest > 0.0) || !(s.safety > 0.0) || !(s.cfl > 0.0) || !(s.grow >= 1.0))
    throw std::invalid_argument("AdaptiveStep: interval, largest step, safety and cfl must be positive, "
                                "grow at least 1");
}

double AdaptiveStep::allowed_step(double structure_dt, double speed_over_h, double cap) const
{
  double step = std::min(settings_.largest, settings_.safety * structure_dt);
  if (speed_over_h > 0.0) step = std::min(step, settings_.cfl / speed_over_h);
  if (cap > 0.0) step = std::min(step, cap);
  if (!(step > 0.0) || !std::isfinite(step))
    throw std::runtime_error("the adaptive step found no positive step (structure estimate " +
                             std::to_string(structure_dt) + " s, max|u|/h " + std::to_string(speed_over_h) +
                             " 1/s)");
  return step;
}

StepLimits extrapolated_limits(const StepLimits& now, const StepLimits& before)
{
  StepLimits end = now;
  if (before.structure_dt > 0.0 && now.structure_dt < before.structure_dt)
    end.structure_dt = now.structure_dt * (now.structure_dt / before.structure_dt);
  if (before.speed_over_h > 0.0 && now.speed_over_h > before.speed_over_h)
    end.speed_over_h = now.speed_over_h * (now.speed_over_h / before.speed_over_h);
  return end;
}

std::int64_t AdaptiveStep::substeps(double interval, double structure_dt, double speed_over_h,
                                    std::int64_t previous, double cap) const
{
  const double allowed = allowed_step(structure_dt, speed_over_h, cap);
  // The fewest equal sub-steps none longer than allowed (a relative 1e-12 spares an extra one where
  // interval / allowed is a whole number up to round-off).
  const auto needed =
      std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil(interval / allowed - 1e-12)));
  if (previous <= 0 || needed >= previous) return needed;
  // Fewer sub-steps only once the allowed step exceeds the previous one by the factor `grow` (to
  // round-off: a relaxed cap is exactly that factor over the step it grew from).
  const double previous_step = interval / static_cast<double>(previous);
  return allowed >= settings_.grow * previous_step * (1.0 - 1e-12) ? needed : previous;
}

double AdaptiveStep::relaxed_cap(double cap) const
{
  if (!(cap > 0.0)) return 0.0;
  const double grown = cap * settings_.grow;
  return grown >= settings_.largest ? 0.0 : grown;
}

} // namespace ibvalve::app
