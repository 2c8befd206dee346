#pragma once
// The body force that makes a chosen (u, p) an exact Navier–Stokes solution (the method of manufactured
// solutions): f = rho (du/dt + u.grad u) + grad p - mu lap u, from the exact fields by central differences
// of step 1e-4 (error about 1e-8, far below any grid's discretisation error in the tests).
#include "fluid/grid.hpp"

namespace ibvalve::fluid::testing {

/// `velocity(x, t)` -> Real3 and `pressure(x, t)` -> double.
template <class Velocity, class Pressure>
Real3 manufactured_force(const Velocity& velocity, const Pressure& pressure, double rho, double mu,
                         const Real3& x, double t)
{
  constexpr double d = 1e-4;
  const Real3 u = velocity(x, t);
  Real3 f{};
  for (int c = 0; c < 3; ++c) {
    const double dudt = (velocity(x, t + d)[c] - velocity(x, t - d)[c]) / (2.0 * d);
    double advection = 0.0, laplacian = 0.0;
    for (int e = 0; e < 3; ++e) {
      Real3 up = x, down = x;
      up[e] += d;
      down[e] -= d;
      const double a = velocity(up, t)[c], b = velocity(down, t)[c];
      advection += u[e] * (a - b) / (2.0 * d);
      laplacian += (a - 2.0 * u[c] + b) / (d * d);
    }
    Real3 up = x, down = x;
    up[c] += d;
    down[c] -= d;
    const double dpdx = (pressure(up, t) - pressure(down, t)) / (2.0 * d);
    f[c] = rho * (dudt + advection) + dpdx - mu * laplacian;
  }
  return f;
}

} // namespace ibvalve::fluid::testing
