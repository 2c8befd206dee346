// What leaves through a traction side (fluid/convection.cpp): fluid leaving the box takes its tangential
// momentum with it. Specification, on a uniform stream (U, 0, W) along x between two traction sides at
// the same pressure, periodic in y and z, inviscid to 1e-10 P (the sides' zero tangential velocity then
// reaches no cell through the viscous term):
//  - beside the outflow side the tangential velocity stays W to solver tolerance, where a flux taking the
//    side's zero tangential velocity out would leave the momentum behind, piling it up at U W / h: to
//    (1 + n U dt / h) W = 2.6 W over these 20 steps (measured so before the fix);
//  - away from the inflow side, whose zero tangential velocity enters at U (1.6 cells over these steps),
//    the stream is untouched;
//  - reversed (entering through the upper side), the same.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <petscsys.h>

#include "fluid/navier_stokes.hpp"

namespace ibvalve::fluid {
namespace {

constexpr double U = 10.0, W = 3.0; // cm/s
constexpr PetscInt nx = 16;         // cells along the stream, h = 0.125 cm
constexpr double dt = 1e-3;         // U dt / h = 0.08
constexpr int steps = 20;

struct Deviation {
  double outflow = 0.0;  // largest |w - W| in the cells beside the outflow side
  double interior = 0.0; // ... in the cells at least 4 from the inflow side
};

Deviation stream(bool reversed)
{
  BoxGeometry box;
  box.lower = {0.0, 0.0, 0.0};
  box.upper = {2.0, 0.5, 0.5};
  box.cells = {nx, 4, 4};
  box.periodic = {false, true, true};
  BoundaryConditions bc;
  for (int upper = 0; upper < 2; ++upper) bc.side(0, upper).kind = SideKind::traction;
  FluidSettings settings;
  settings.rho = 1.0;
  settings.mu = 1e-10;
  settings.solver = SolverKind::krylov;
  settings.subsolver = SubsolverKind::amg;
  settings.rtol = 1e-13;
  settings.atol = 1e-14;
  NavierStokes fluid(PETSC_COMM_WORLD, box, bc, settings);
  const double sign = reversed ? -1.0 : 1.0;
  fluid.set_initial_condition([&](const Real3&, double) { return Real3{sign * U, 0.0, W}; }, nullptr, 0.0);
  for (int n = 0; n < steps; ++n) fluid.step(dt);

  const StaggeredGrid& grid = fluid.grid();
  StagArray u(grid, fluid.state(), true);
  const PetscInt slot = grid.face_slot(2);
  const PetscInt outflow = reversed ? 0 : nx - 1;
  Deviation d;
  for (PetscInt k = grid.begin(2); k < grid.begin(2) + grid.count(2); ++k)
    for (PetscInt j = grid.begin(1); j < grid.begin(1) + grid.count(1); ++j)
      for (PetscInt i = grid.begin(0); i < grid.begin(0) + grid.count(0); ++i) {
        const double deviation = std::abs(u(i, j, k, slot) - W);
        if (i == outflow) d.outflow = std::max(d.outflow, deviation);
        const PetscInt from_inflow = reversed ? nx - 1 - i : i;
        if (from_inflow >= 4) d.interior = std::max(d.interior, deviation);
      }
  MPI_Allreduce(MPI_IN_PLACE, &d.outflow, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD);
  MPI_Allreduce(MPI_IN_PLACE, &d.interior, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD);
  return d;
}

TEST(OutflowMomentum, TheTangentialVelocityLeavesWithTheFluid)
{
  for (const bool reversed : {false, true}) {
    const Deviation d = stream(reversed);
    PetscPrintf(PETSC_COMM_WORLD,
                "%s: |w - W| beside the outflow side %.3e, 4 cells or more from the inflow %.3e "
                "(a flux without the momentum: w piles up to %.2f W)\n",
                reversed ? "reversed" : "forward", d.outflow, d.interior, 1.0 + steps * U * dt / 0.125);
    EXPECT_LT(d.outflow, 1e-9 * W);
    EXPECT_LT(d.interior, 1e-9 * W);
  }
}

} // namespace
} // namespace ibvalve::fluid
