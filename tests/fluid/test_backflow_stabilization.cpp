// Backflow stabilization of traction sides (fluid/boundary.hpp, BoundarySide::backflow): where fluid
// enters, the side's pressure is lowered by beta rho/2 (u.n)^2. Specification, on plug flow along x between
// two traction sides of a box (the other sides are no-slip walls, but with a viscosity of 1e-10 P their
// shear is negligible; the uniform flow has no convection, so it stays a plug):
//  - without stabilization the plug accelerates at the constant rate (p_in - p_out) / (rho L), to
//    solver tolerance;
//  - with beta = 1 the inflow side's pressure is the total pressure of a reservoir at rest, and the plug
//    obeys rho L dU/dt = dp - rho U^2 / 2: U(t) = U_inf tanh(U_inf t / (2 L)), U_inf = sqrt(2 dp / rho)
//    (Bernoulli efflux). The drop is taken from the state at the start of the step, so the error falls
//    at first order in the time step;
//  - only inflow is affected: the same flow reversed, entering through the other side, gives the same
//    speed; the outflow side keeps its static pressure;
//  - 1 rank and 2 ranks agree to solver tolerance.
#include <gtest/gtest.h>

#include <cmath>

#include <petscsys.h>

#include "fluid/navier_stokes.hpp"

namespace ibvalve::fluid {
namespace {

constexpr double length = 2.0;        // cm between the traction sides
constexpr double pressure_drop = 200; // dyn/cm^2
constexpr double rho = 1.0;

/// The mean x velocity after `steps` steps of dt, driven by `pressure_drop` from the lower side to the
/// upper one (or from the upper to the lower when `reversed`).
double plug_velocity(double beta, bool reversed, double dt, int steps)
{
  BoxGeometry box;
  box.lower = {0.0, 0.0, 0.0};
  box.upper = {length, 0.5, 0.5};
  box.cells = {16, 8, 8};
  box.periodic = {false, false, false};
  BoundaryConditions bc;
  for (int s = 2; s < 6; ++s) bc.side(s).kind = SideKind::velocity;
  for (int upper = 0; upper < 2; ++upper) {
    BoundarySide& side = bc.side(0, upper);
    side.kind = SideKind::traction;
    side.backflow = beta;
  }
  bc.side(0, reversed ? 1 : 0).pressure = [](const Real3&, double) { return pressure_drop; };
  FluidSettings settings;
  settings.rho = rho;
  settings.mu = 1e-10; // a plug: the no-slip sides' shear changes U by about nu t / h^2 = 5e-9
  settings.solver = SolverKind::krylov;
  settings.subsolver = SubsolverKind::amg;
  settings.rtol = 1e-13;
  settings.atol = 1e-14;
  NavierStokes fluid(PETSC_COMM_WORLD, box, bc, settings);
  fluid.set_initial_condition([](const Real3&, double) { return Real3{0.0, 0.0, 0.0}; }, nullptr, 0.0);
  for (int n = 0; n < steps; ++n) fluid.step(dt);

  const StaggeredGrid& grid = fluid.grid();
  StagArray u(grid, fluid.state(), true);
  double sums[2] = {0.0, 0.0};
  for (PetscInt k = grid.begin(2); k < grid.begin(2) + grid.count(2); ++k)
    for (PetscInt j = grid.begin(1); j < grid.begin(1) + grid.count(1); ++j)
      for (PetscInt i = grid.begin(0); i < grid.face_end(0, 0); ++i) {
        sums[0] += u(i, j, k, grid.face_slot(0));
        sums[1] += 1.0;
      }
  MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD);
  return sums[0] / sums[1];
}

double bernoulli_efflux(double t)
{
  const double u_inf = std::sqrt(2.0 * pressure_drop / rho);
  return u_inf * std::tanh(u_inf * t / (2.0 * length));
}

TEST(BackflowStabilization, WithoutItThePlugAcceleratesUniformly)
{
  const double dt = 0.01, t = 0.2;
  const double u = plug_velocity(0.0, false, dt, 20);
  const double exact = pressure_drop * t / (rho * length);
  PetscPrintf(PETSC_COMM_WORLD, "beta = 0: U(%.2f) = %.12f, p/(rho L) t = %.12f\n", t, u, exact);
  EXPECT_NEAR(u, exact, 2e-8 * exact); // the walls' shear, nu t / h^2 = 5e-9
}

TEST(BackflowStabilization, TheInflowSideCarriesTheTotalPressure)
{
  // t = 2 L / U_inf: the plug has reached tanh(1) = 76 % of its final speed.
  const double t = 2.0 * length / std::sqrt(2.0 * pressure_drop / rho);
  const double exact = bernoulli_efflux(t);
  double errors[3];
  for (int level = 0; level < 3; ++level) {
    const int steps = 10 << level;
    const double u = plug_velocity(1.0, false, t / steps, steps);
    errors[level] = std::abs(u - exact);
    PetscPrintf(PETSC_COMM_WORLD, "beta = 1, %3d steps: U = %.8f, Bernoulli efflux %.8f, error %.3e\n", steps,
                u, exact, errors[level]);
  }
  const double order1 = std::log2(errors[0] / errors[1]), order2 = std::log2(errors[1] / errors[2]);
  PetscPrintf(PETSC_COMM_WORLD, "orders in the time step: %.3f %.3f\n", order1, order2);
  // First order: the drop lags one step behind the velocity it depends on.
  EXPECT_GT(order1, 0.9);
  EXPECT_GT(order2, 0.9);
  EXPECT_LT(errors[2], 0.01 * exact);
}

TEST(BackflowStabilization, OnlyInflowFacesAreAffected)
{
  const double t = 0.1, dt = 0.005;
  const int steps = 20;
  const double forward = plug_velocity(1.0, false, dt, steps), backward = plug_velocity(1.0, true, dt, steps);
  PetscPrintf(PETSC_COMM_WORLD, "forward %.12f, reversed %.12f\n", forward, backward);
  EXPECT_GT(forward, 0.0);
  EXPECT_NEAR(backward, -forward, 1e-9 * forward);
  // Slower than without stabilization (the inflow pays rho U^2 / 2), faster than the final speed allows.
  EXPECT_LT(forward, pressure_drop * t / (rho * length));
  EXPECT_NEAR(forward, bernoulli_efflux(t), 0.05 * bernoulli_efflux(t));
}

} // namespace
} // namespace ibvalve::fluid
