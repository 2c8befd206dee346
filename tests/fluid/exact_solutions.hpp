#pragma once
// Exact Navier–Stokes solutions the fluid tests and benchmark measure against.
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "fluid/exact_vortex.hpp"
#include "fluid/navier_stokes.hpp"
#include "fluid/queries.hpp"

namespace ibvalve::fluid::testing {

/// The Taylor–Green vortex in x-y on the unit cube, carried by the uniform velocity (1, 1, 1) so that
/// convection works in every direction (fluid/exact_vortex.hpp; rho = 1, nu = 0.01).
struct AdvectedTaylorGreen : ExactVortex {
  AdvectedTaylorGreen() { mean = {1.0, 1.0, 1.0}; }
};

/// The ABC (Arnold–Beltrami–Childress) flow with mean advection of docs/reference.md, "Targets"
/// (fluid/exact_vortex.hpp; rho = 1, A = B = C = 1, nu = 0.01).
struct AbcFlow : ExactVortex {
  AbcFlow()
  {
    kind = Kind::abc;
    mean = {1.0, 1.0, 1.0};
  }
};

inline double order(double coarse_error, double fine_error)
{
  return std::log2(coarse_error / fine_error);
}

} // namespace ibvalve::fluid::testing
