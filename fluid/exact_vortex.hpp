#pragma once
// Exact decaying vortices of the incompressible Navier–Stokes equations in a periodic box, carried by a
// uniform velocity `mean` (Galilean invariance keeps them exact): what the fluid's verification runs and
// the `fluid` model's error columns measure against.
//  - Taylor–Green in x-y (Taylor & Green 1937): u = m_x - A cos X sin Y E, v = m_y + A sin X cos Y E,
//    w = m_z, p = -rho/4 A^2 (cos 2X + cos 2Y) E^2, E = exp(-2 k^2 nu t);
//  - ABC (Arnold–Beltrami–Childress, A = B = C): u = m + A E (cos Y + sin Z, sin X + cos Z, cos X + sin Y),
//    p = -rho A^2 E^2 (cos Y sin Z + sin X cos Z + cos X sin Y), E = exp(-k^2 nu t);
// with X = k (x - x_0 - m_x t) (and Y, Z alike), k = 2 pi / L (the box's length in x).
#include <cmath>
#include <numbers>

#include "fluid/grid.hpp"

namespace ibvalve::fluid {

struct ExactVortex {
  enum class Kind { taylor_green, abc };
  Kind kind = Kind::taylor_green;
  Real3 lower{0.0, 0.0, 0.0}, length{1.0, 1.0, 1.0}, mean{0.0, 0.0, 0.0};
  double amplitude = 1.0, nu = 0.01, rho = 1.0;

  double phase(const Real3& x, double t, int d) const
  {
    return 2.0 * std::numbers::pi * (x[d] - lower[d] - mean[d] * t) / length[d];
  }
  double wave_number() const { return 2.0 * std::numbers::pi / length[0]; }

  Real3 velocity(const Real3& x, double t) const
  {
    const double X = phase(x, t, 0), Y = phase(x, t, 1), Z = phase(x, t, 2), k = wave_number();
    if (kind == Kind::taylor_green) {
      const double e = amplitude * std::exp(-2.0 * k * k * nu * t);
      return {mean[0] - std::cos(X) * std::sin(Y) * e, mean[1] + std::sin(X) * std::cos(Y) * e, mean[2]};
    }
    const double e = amplitude * std::exp(-k * k * nu * t);
    return {mean[0] + e * (std::cos(Y) + std::sin(Z)), mean[1] + e * (std::sin(X) + std::cos(Z)),
            mean[2] + e * (std::cos(X) + std::sin(Y))};
  }

  double pressure(const Real3& x, double t) const
  {
    const double X = phase(x, t, 0), Y = phase(x, t, 1), Z = phase(x, t, 2), k = wave_number();
    if (kind == Kind::taylor_green) {
      const double e = amplitude * amplitude * std::exp(-4.0 * k * k * nu * t);
      return -0.25 * rho * (std::cos(2.0 * X) + std::cos(2.0 * Y)) * e;
    }
    const double e = amplitude * amplitude * std::exp(-2.0 * k * k * nu * t);
    return -rho * e * (std::cos(Y) * std::sin(Z) + std::sin(X) * std::cos(Z) + std::cos(X) * std::sin(Y));
  }
};

} // namespace ibvalve::fluid
