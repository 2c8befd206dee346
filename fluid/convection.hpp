#pragma once
// The convective term N(u) = div(u u) on the MAC grid, in conservative form, with upwind-biased,
// limited face values.
//
// Each momentum control volume (centred on a face) exchanges momentum through its six sides. The
// advecting velocity on a side is the average of the two neighbouring normal velocities (second
// order); the advected velocity there is reconstructed from the upwind side by the kappa = 1/3
// upwind-biased scheme (third-order face value; van Leer 1985, "Upwind-difference methods for
// aerodynamic problems governed by the Euler equations") limited by Koren's limiter (Koren 1993,
// "A robust upwind discretization method for advection, diffusion and source terms"), which keeps
// the scheme TVD. A TVD limiter clips smooth extrema and costs accuracy there; following the smooth-
// extremum test of Colella & Sekora (2008, JCP 227:7069), the limiter is skipped where the
// second differences on both sides of the face agree in sign and are within a factor two of each
// other (a smooth extremum rather than a jump).
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include <petscvec.h>

#include "fluid/boundary.hpp"
#include "fluid/grid.hpp"

namespace ibvalve::fluid {

enum class ConvectionScheme { limited_upwind, centered };

/// c ? a : b by bit masks, which the compiler keeps as a select: as a conditional on data that
/// changes from face to face it may be compiled to a branch, mispredicted wherever the flow is not
/// smooth.
inline double select(bool c, double a, double b)
{
  const std::uint64_t mask = -static_cast<std::uint64_t>(c);
  return std::bit_cast<double>((std::bit_cast<std::uint64_t>(a) & mask) |
                               (std::bit_cast<std::uint64_t>(b) & ~mask));
}

/// The face value between the upwind value w0 and the downwind value wp, given the further upwind
/// value wm and the further downwind value wpp (limited kappa = 1/3 reconstruction).
inline double limited_face_value(double wm, double w0, double wp, double wpp)
{
  // Without branches (select): the limiter's cases depend on the data.
  const double d1 = w0 - wm, d2 = wp - w0;
  const double unlimited = w0 + (d1 + 2.0 * d2) / 6.0;
  const double bound =
      std::min(std::min(2.0 * std::abs(d1), 2.0 * std::abs(d2)), std::abs(d1 + 2.0 * d2) / 3.0);
  const double limited_slope = select(d1 * d2 > 0.0, std::copysign(bound, d1), 0.0);
  const double limited = w0 + 0.5 * limited_slope;
  // Smooth extremum (or smooth steep region): consistent curvature on both sides of the face.
  const double c0 = d2 - d1, c1 = wpp - 2.0 * wp + w0;
  const bool smooth =
      (c0 * c1 > 0.0) & (std::abs(c0) <= 2.0 * std::abs(c1)) & (std::abs(c1) <= 2.0 * std::abs(c0));
  return select(smooth, unlimited, limited);
}

/// out = N(u) on every owned face that is not a velocity-boundary face (those get 0). `u` is a local
/// vector with ghosts filled (exchange + fill_ghosts); `out` is a local vector of the same grid. On
/// the momentum-cell sides that lie on a wall the advected (tangential) velocity is the wall's, from
/// `bc` at time t, rather than a reconstruction from ghosts.
void convective_term(const StaggeredGrid& grid, const BoundaryConditions& bc, double t, Vec u, Vec out,
                     ConvectionScheme scheme);

} // namespace ibvalve::fluid
