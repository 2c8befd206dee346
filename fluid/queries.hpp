#pragma once
// What the rest of the code asks of the flow: fluxes through disks and rectangles, values at points,
// global norms, and errors against exact solutions (for verification). Every function is
// collective over the grid's communicator and returns the same value on every rank.
#include <array>

#include "fluid/navier_stokes.hpp"
#include "fluid/plane_region.hpp"

namespace ibvalve::fluid {

/// Volume flux int u.n dA over the region. On a face plane the face velocities are summed; between
/// face planes they are interpolated linearly along the normal.
double volume_flux(const NavierStokes& fluid, const PlaneRegion& region);

/// Velocity at a point (trilinear interpolation of each component from its faces).
Real3 velocity_at(const NavierStokes& fluid, const Real3& x);
/// Pressure (at fluid.pressure_time()) at a point, trilinear from cell centres.
double pressure_at(const NavierStokes& fluid, const Real3& x);

/// The largest |u| over the cell centres (each component the mean of the cell's two faces), or over
/// those `region` holds when it is given (0 when it holds none).
double max_velocity_magnitude(const NavierStokes& fluid, const PointSet& region = nullptr);

double kinetic_energy(const NavierStokes& fluid); // 1/2 rho int |u|^2
double enstrophy(const NavierStokes& fluid);      // 1/2 int |omega|^2 (cell-centred omega)
double max_divergence(const NavierStokes& fluid); // max over cells of |D u|

/// Cell-centred velocity (3 values per cell) and vorticity (3 per cell) and pressure (1 per cell) of
/// the owned cells, C order (z slowest, x fastest; components last), for output.
struct CellFields {
  std::vector<double> velocity, vorticity, pressure;
  Index3 begin{}, count{};
};
CellFields cell_fields(const NavierStokes& fluid);

struct FieldErrors {
  double velocity_l2 = 0.0, velocity_max = 0.0, pressure_l2 = 0.0, pressure_max = 0.0;
};
/// Discrete L2 (root mean square over the box) and max errors of u at time() on the faces and of p at
/// pressure_time() in the cells. With `pressure_up_to_constant` both pressures have their mean removed.
FieldErrors field_errors(const NavierStokes& fluid, const VelocityFunction& exact_velocity,
                         const ScalarFunction& exact_pressure, bool pressure_up_to_constant);

} // namespace ibvalve::fluid
