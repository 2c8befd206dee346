#include "windkessel/lumped_valve.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace ibvalve::windkessel {

LumpedSystem::State LumpedSystem::rate(double t, const State& y) const
{
  const double q = y[0], zeta = std::clamp(y[1], 0.0, 1.0);
  const double dp = lv_pressure(t) - aortic_pressure(y);
  const double area = valve.area(zeta);
  const double bernoulli = valve.density / (2.0 * area * area);
  const double inertance = valve.density * valve.effective_length / area;
  double dzeta = 0.0;
  if (dp > valve.opening_pressure)
    dzeta = (1.0 - zeta) * valve.opening_rate * (dp - valve.opening_pressure);
  else if (dp < valve.closing_pressure)
    dzeta = zeta * valve.closing_rate * (dp - valve.closing_pressure);
  return {(dp - bernoulli * q * std::abs(q)) / inertance, dzeta, outlet.reservoir_rate(y[2], q)};
}

LumpedSystem::State LumpedSystem::step(double t, const State& y, double dt) const
{
  auto axpy = [](const State& a, double s, const State& b) {
    return State{a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]};
  };
  const State k1 = rate(t, y);
  const State k2 = rate(t + 0.5 * dt, axpy(y, 0.5 * dt, k1));
  const State k3 = rate(t + 0.5 * dt, axpy(y, 0.5 * dt, k2));
  const State k4 = rate(t + dt, axpy(y, dt, k3));
  State next;
  for (std::size_t i = 0; i < 3; ++i) next[i] = y[i] + dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
  next[1] = std::clamp(next[1], 0.0, 1.0);
  return next;
}

} // namespace ibvalve::windkessel
