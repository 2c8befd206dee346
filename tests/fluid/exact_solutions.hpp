#pragma once
// Exact Navier–Stokes solutions the fluid tests and benchmark measure against.
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "fluid/navier_stokes.hpp"
#include "fluid/queries.hpp"

namespace ibvalve::fluid::testing {

constexpr double two_pi = 2.0 * std::numbers::pi;

/// A Taylor–Green vortex in x-y on the unit cube, carried by the uniform velocity (1, 1, 1)
/// (Galilean invariance keeps it exact), so convection works in every direction:
/// u = 1 - cos(2 pi X) sin(2 pi Y) E, v = 1 + sin(2 pi X) cos(2 pi Y) E, w = 1,
/// p = -rho/4 (cos 4 pi X + cos 4 pi Y) E^2, X = x - t, Y = y - t, E = exp(-8 pi^2 nu t).
struct AdvectedTaylorGreen {
  double rho = 1.0, mu = 0.01;
  Real3 velocity(const Real3& x, double t) const
  {
    const double e = std::exp(-2.0 * two_pi * two_pi * mu / rho * t);
    const double X = two_pi * (x[0] - t), Y = two_pi * (x[1] - t);
    return {1.0 - std::cos(X) * std::sin(Y) * e, 1.0 + std::sin(X) * std::cos(Y) * e, 1.0};
  }
  double pressure(const Real3& x, double t) const
  {
    const double e = std::exp(-2.0 * two_pi * two_pi * mu / rho * t);
    const double X = two_pi * (x[0] - t), Y = two_pi * (x[1] - t);
    return -0.25 * rho * (std::cos(2.0 * X) + std::cos(2.0 * Y)) * e * e;
  }
};

/// The ABC (Arnold–Beltrami–Childress) flow with mean advection of docs/reference.md, "Targets"
/// (rho = 1, A = B = C = 1).
struct AbcFlow {
  double mu = 0.01;
  Real3 velocity(const Real3& x, double t) const
  {
    const double e = std::exp(-two_pi * two_pi * mu * t);
    const double X = two_pi * (x[0] - t), Y = two_pi * (x[1] - t), Z = two_pi * (x[2] - t);
    return {1.0 + e * (std::cos(Y) + std::sin(Z)), 1.0 + e * (std::sin(X) + std::cos(Z)),
            1.0 + e * (std::cos(X) + std::sin(Y))};
  }
  double pressure(const Real3& x, double t) const
  {
    const double e = std::exp(-2.0 * two_pi * two_pi * mu * t);
    const double X = two_pi * (x[0] - t), Y = two_pi * (x[1] - t), Z = two_pi * (x[2] - t);
    return -e * (std::cos(Y) * std::sin(Z) + std::sin(X) * std::cos(Z) + std::cos(X) * std::sin(Y));
  }
};

inline double order(double coarse_error, double fine_error)
{
  return std::log2(coarse_error / fine_error);
}

} // namespace ibvalve::fluid::testing
