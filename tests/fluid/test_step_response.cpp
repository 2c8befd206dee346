// A step's response to its body force (fluid/navier_stokes.hpp, stokes_response and add_to_state): a
// step is linear in its body force f (convection extrapolated from u^n and u^{n-1}, boundary data
// independent of f), so the step taken with f equals the step taken without it plus the Stokes solve
// of the step's operator for f from rest with homogeneous boundary data. Checked after a first step,
// so that the step compared extrapolates its convection from two earlier states: in a periodic box
// (FFT solver, exact) to round-off; in a box with a moving lid and in one between two pressure sides
// walled outside a disc (Krylov solver, FGMRES to a relative 1e-12) to 1e-10 of the state. Without
// the boundary rows of the response's right side set to zero (the wall's data are the free step's),
// the lid box's differ by 3e2 of the state.
#include <cmath>
#include <cstdio>
#include <numbers>

#include <gtest/gtest.h>

#include "fluid/navier_stokes.hpp"
#include "io/petsc_check.hpp"

using namespace ibvalve;
using namespace ibvalve::fluid;

namespace {

Real3 flow(const Real3& x, double)
{
  const double k = 2.0 * std::numbers::pi;
  return Real3{std::sin(k * x[1]) * std::sin(k * x[0]), std::sin(k * x[2]), std::sin(k * x[0]) * x[1]};
}

Real3 force(const Real3& x, double)
{
  return Real3{1e3 * std::exp(-40.0 * (std::pow(x[0] - 0.5, 2) + std::pow(x[1] - 0.4, 2))), 0.0,
               -5e2 * std::cos(2.0 * std::numbers::pi * x[0])};
}

/// The largest difference between the two ways of taking a second step, over the state's size.
double superposition_gap(const BoxGeometry& box, const BoundaryConditions& bc, const FluidSettings& settings)
{
  NavierStokes forced(PETSC_COMM_WORLD, box, bc, settings), free(PETSC_COMM_WORLD, box, bc, settings);
  const double dt = 2e-3;
  for (NavierStokes* f : {&forced, &free}) {
    f->set_initial_condition(flow, nullptr, 0.0);
    f->step(dt);
  }
  forced.set_body_force(force, dt);
  forced.step(dt);
  free.set_body_force(force, dt);
  petsc::OwnedVec response = free.grid().create_local();
  free.stokes_response(free.body_force(), dt, response);
  free.set_body_force([](const Real3&, double) { return Real3{0.0, 0.0, 0.0}; }, dt);
  free.step(dt);
  free.add_to_state(response);
  petsc::OwnedVec a = forced.grid().create_global(), b = forced.grid().create_global(),
                  r = forced.grid().create_global();
  PETSC_CHECK(DMLocalToGlobal(forced.grid().dm(), forced.state(), INSERT_VALUES, a));
  PETSC_CHECK(DMLocalToGlobal(free.grid().dm(), free.state(), INSERT_VALUES, b));
  PETSC_CHECK(DMLocalToGlobal(free.grid().dm(), response, INSERT_VALUES, r));
  double size = 0.0, change = 0.0, gap = 0.0;
  PETSC_CHECK(VecNorm(a, NORM_INFINITY, &size));
  PETSC_CHECK(VecNorm(r, NORM_INFINITY, &change));
  PETSC_CHECK(VecAXPY(a, -1.0, b));
  PETSC_CHECK(VecNorm(a, NORM_INFINITY, &gap));
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0)
    std::printf("largest difference %.3g, state %.3g, the force's response %.3g\n", gap, size, change);
  EXPECT_GT(change, 1e-2 * size); // the force matters
  return gap / size;
}

} // namespace

TEST(StepResponse, APeriodicStepIsItsFreeStepPlusItsResponseToTheForce)
{
  BoxGeometry box;
  box.cells = {16, 16, 16};
  FluidSettings settings;
  settings.mu = 0.1;
  EXPECT_LT(superposition_gap(box, BoundaryConditions::all_periodic(), settings), 1e-13);
}

TEST(StepResponse, AWalledStepIsItsFreeStepPlusItsResponseToTheForce)
{
  BoxGeometry box;
  box.cells = {12, 10, 14};
  box.periodic = {false, false, false};
  BoundaryConditions bc;
  for (int s = 0; s < 6; ++s) bc.side(s).kind = SideKind::velocity;
  bc.side(3).velocity = [](const Real3&, double t) { return Real3{1.0 + t, 0.0, 0.0}; }; // the lid, y = 1
  FluidSettings settings;
  settings.mu = 0.1;
  settings.solver = SolverKind::krylov;
  EXPECT_LT(superposition_gap(box, bc, settings), 1e-10);
}

TEST(StepResponse, AStepBetweenPressureSidesIsItsFreeStepPlusItsResponseToTheForce)
{
  // The valve's sides: a pressure inlet and outlet (backflow stabilised), walled outside a disc.
  BoxGeometry box;
  box.cells = {12, 12, 16};
  box.periodic = {false, false, false};
  BoundaryConditions bc;
  for (int s = 0; s < 4; ++s) bc.side(s).kind = SideKind::velocity;
  for (int s = 4; s < 6; ++s) {
    bc.side(s).kind = SideKind::traction;
    bc.side(s).wall = [](const Real3& x) { return std::hypot(x[0] - 0.5, x[1] - 0.5) > 0.35; };
    bc.side(s).backflow = 1.0;
  }
  bc.side(4).pressure = [](const Real3&, double t) { return 50.0 * (1.0 + t); };
  FluidSettings settings;
  settings.mu = 0.1;
  settings.solver = SolverKind::krylov;
  EXPECT_LT(superposition_gap(box, bc, settings), 1e-10);
}
