#include "windkessel/lumped_valve.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace ibvalve::windkessel {

std::array<double, 2> ValveParameters::rates(double dp, double q, double zeta_in) const
{
  const double zeta = std::clamp(zeta_in, 0.0, 1.0);
  const double a = area(zeta);
  const double bernoulli = density / (2.0 * a * a);
  const double inertance = density * effective_length / a;
  double dzeta = 0.0;
  if (dp > opening_pressure)
    dzeta = (1.0 - zeta) * opening_rate * (dp - opening_pressure);
  else if (dp < closing_pressure)
    dzeta = zeta * closing_rate * (dp - closing_pressure);
  return {(dp - bernoulli * q * std::abs(q)) / inertance, dzeta};
}

LumpedSystem::State LumpedSystem::rate(double t, const State& y) const
{
  const double q = y[0];
  const auto [dq, dzeta] = valve.rates(lv_pressure(t) - aortic_pressure(y), q, y[1]);
  return {dq, dzeta, outlet.reservoir_rate(y[2], q)};
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
