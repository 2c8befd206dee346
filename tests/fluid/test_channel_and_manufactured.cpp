// Boundary conditions: a channel between plates driven by traction (pressure) sides reproduces the
// parabolic profile to solver tolerance, and a time-dependent manufactured solution with velocity
// sides (prescribed, moving walls) and traction sides (a position- and time-dependent boundary
// pressure) converges at second order in velocity and pressure.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "fluid/queries.hpp"
#include "tests/fluid/exact_solutions.hpp"

namespace ibvalve::fluid {
namespace {

using std::cos;
using std::sin;
constexpr double pi = std::numbers::pi;
constexpr double A = 2.0 * pi;

int rank()
{
  int r = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &r);
  return r;
}

TEST(Channel, TractionDrivenFlowBetweenPlatesIsTheParabolaToSolverTolerance)
{
  // x in [0, 2]: traction sides with p = 1 at x = 0 and p = 0 at x = 2; no-slip plates at y = 0, 1;
  // periodic in z. Steady solution u = G/(2 mu) y (1 - y), G = 1/2, p = 1 - x/2.
  BoxGeometry box;
  box.upper = {2.0, 1.0, 1.0};
  box.cells = {8, 8, 4};
  box.periodic = {false, false, true};
  BoundaryConditions bc;
  bc.side(0, 0).kind = SideKind::traction;
  bc.side(0, 0).pressure = [](const Real3&, double) { return 1.0; };
  bc.side(0, 1).kind = SideKind::traction;
  bc.side(1, 0).kind = SideKind::velocity;
  bc.side(1, 1).kind = SideKind::velocity;
  FluidSettings settings;
  settings.rho = 1.0;
  settings.mu = 0.1;
  settings.solver = SolverKind::krylov;
  settings.rtol = 1e-13;
  NavierStokes fluid(PETSC_COMM_WORLD, box, bc, settings);
  const double G = 0.5;
  auto exact_u = [&](const Real3& x, double) {
    return Real3{G / (2.0 * settings.mu) * x[1] * (1.0 - x[1]), 0.0, 0.0};
  };
  auto exact_p = [](const Real3& x, double) { return 1.0 - 0.5 * x[0]; };
  // Start from the parabola and let the coupled solver advance it: the parabola is the discrete
  // steady state (the MAC Laplacian with quadratic wall ghosts is exact on quadratics, the pressure
  // is linear), so any drift measures a flaw in the boundary treatment or the solve.
  fluid.set_initial_condition([&](const Real3& x, double t) { return exact_u(x, t); }, exact_p, 0.0);
  for (int s = 0; s < 10; ++s) fluid.step(0.05);
  const FieldErrors e = field_errors(fluid, exact_u, exact_p, false);
  const double umax = G / (8.0 * settings.mu);
  if (rank() == 0)
    std::printf("channel 8x8x4: max |u - parabola| / u_max = %.2e, max |p - p_exact| = %.2e\n",
                e.velocity_max / umax, e.pressure_max);
  EXPECT_LT(e.velocity_max / umax, 1e-8);
  EXPECT_LT(e.pressure_max, 1e-8);
  // Conservation: what enters through x = 0 leaves through x = 2 and through every plane between.
  const auto inflow = volume_flux(fluid, PlaneRegion::rectangle(0, 0.0, {0, 0, 0}, {2, 1, 1}));
  const auto outflow = volume_flux(fluid, PlaneRegion::rectangle(0, 2.0, {0, 0, 0}, {2, 1, 1}));
  const auto middle = volume_flux(fluid, PlaneRegion::rectangle(0, 0.77, {0, 0, 0}, {2, 1, 1}));
  // The discrete flux is the midpoint sum of the parabola over the cells of the inflow side.
  double midpoint_sum = 0.0;
  for (int j = 0; j < 8; ++j) {
    const double y = (j + 0.5) / 8.0;
    midpoint_sum += G / (2.0 * settings.mu) * y * (1.0 - y) / 8.0;
  }
  EXPECT_NEAR(inflow, midpoint_sum, 1e-12);
  EXPECT_NEAR(outflow, inflow, 1e-12 * inflow);
  EXPECT_NEAR(middle, inflow, 1e-12 * inflow);
}

/// u = curl(0, 0, Psi) with Psi = f(t) cos(pi x) sin(A y) Z(z) / A, Z = 1 + sin(A z)/2,
/// f = 1 + sin(A t)/2; w = 0. v = 0 on x = 0, 1 and du/dx = 0 there, so x sides are traction sides
/// with p_b = p. p = f (x^2 + sin(A y) cos(A z)).
struct Manufactured {
  double rho = 1.0, mu = 0.05;
  static double f(double t) { return 1.0 + 0.5 * sin(A * t); }
  static double df(double t) { return 0.5 * A * cos(A * t); }
  static double Z(double z) { return 1.0 + 0.5 * sin(A * z); }
  static double d2Z(double z) { return -0.5 * A * A * sin(A * z); }
  Real3 velocity(const Real3& x, double t) const
  {
    return {f(t) * cos(pi * x[0]) * cos(A * x[1]) * Z(x[2]),
            f(t) * pi / A * sin(pi * x[0]) * sin(A * x[1]) * Z(x[2]), 0.0};
  }
  double pressure(const Real3& x, double t) const
  {
    return f(t) * (x[0] * x[0] + sin(A * x[1]) * cos(A * x[2]));
  }
  Real3 force(const Real3& x, double t) const
  {
    const double F = f(t), z = Z(x[2]), cx = cos(pi * x[0]), sx = sin(pi * x[0]), cy = cos(A * x[1]),
                 sy = sin(A * x[1]);
    const double u = F * cx * cy * z, v = F * pi / A * sx * sy * z;
    const double ux = -F * pi * sx * cy * z, uy = -F * A * cx * sy * z;
    const double vx = F * pi * pi / A * cx * sy * z, vy = F * pi * sx * cy * z;
    const double lap_u = -(pi * pi + A * A) * u + F * cx * cy * d2Z(x[2]);
    const double lap_v = -(pi * pi + A * A) * v + F * pi / A * sx * sy * d2Z(x[2]);
    const double ut = df(t) / F * u, vt = df(t) / F * v;
    const double px = 2.0 * F * x[0], py = F * A * cy * cos(A * x[2]), pz = -F * A * sy * sin(A * x[2]);
    return {rho * (ut + u * ux + v * uy) + px - mu * lap_u, rho * (vt + u * vx + v * vy) + py - mu * lap_v,
            pz};
  }
};

FieldErrors run_manufactured(PetscInt n, double final_time)
{
  const Manufactured m;
  BoxGeometry box;
  box.cells = {n, n, n};
  box.periodic = {false, false, true};
  BoundaryConditions bc;
  for (int upper = 0; upper < 2; ++upper) {
    bc.side(0, upper).kind = SideKind::traction;
    bc.side(0, upper).pressure = [m](const Real3& x, double t) { return m.pressure(x, t); };
    bc.side(1, upper).kind = SideKind::velocity;
    bc.side(1, upper).velocity = [m](const Real3& x, double t) { return m.velocity(x, t); };
  }
  FluidSettings settings;
  settings.rho = m.rho;
  settings.mu = m.mu;
  settings.solver = SolverKind::krylov;
  settings.rtol = 1e-11;
  NavierStokes fluid(PETSC_COMM_WORLD, box, bc, settings);
  auto u = [&](const Real3& x, double t) { return m.velocity(x, t); };
  auto p = [&](const Real3& x, double t) { return m.pressure(x, t); };
  fluid.set_initial_condition(u, p, 0.0);
  const int steps = static_cast<int>(std::lround(final_time * static_cast<double>(n) / 0.25));
  const double dt = final_time / steps;
  double worst_divergence = 0.0;
  for (int s = 0; s < steps; ++s) {
    fluid.set_body_force([&](const Real3& x, double t) { return m.force(x, t); }, fluid.time() + 0.5 * dt);
    fluid.step(dt);
    worst_divergence =
        std::max(worst_divergence, max_divergence(fluid) / (max_velocity_magnitude(fluid) * n));
  }
  EXPECT_LT(worst_divergence, 1e-10) << "n = " << n;
  if (rank() == 0)
    std::printf("manufactured %2d^3: %d steps, %.1f Krylov iterations per step, max |div u| h/|u| %.1e\n",
                static_cast<int>(n), steps, static_cast<double>(fluid.statistics().solver_iterations) / steps,
                worst_divergence);
  return field_errors(fluid, u, p, false);
}

TEST(Manufactured, VelocityAndTractionSidesAreSecondOrder)
{
  // ctest: 10^3, 20^3, 40^3 to t = 0.125; nightly (-fluid_test_nightly): 16^3, 32^3, 64^3 to t = 0.25.
  PetscBool nightly = PETSC_FALSE;
  PetscOptionsHasName(nullptr, nullptr, "-fluid_test_nightly", &nightly);
  const PetscInt base = nightly ? 16 : 10;
  const PetscInt grids[3] = {base, 2 * base, 4 * base};
  std::vector<FieldErrors> errors;
  for (PetscInt n : grids) errors.push_back(run_manufactured(n, nightly ? 0.25 : 0.125));
  for (std::size_t g = 0; g < 3; ++g) {
    if (rank() == 0)
      std::printf("manufactured %2d^3: u L2 %.3e max %.3e | p L2 %.3e max %.3e\n", static_cast<int>(grids[g]),
                  errors[g].velocity_l2, errors[g].velocity_max, errors[g].pressure_l2,
                  errors[g].pressure_max);
    if (g == 0) continue;
    const double ou2 = testing::order(errors[g - 1].velocity_l2, errors[g].velocity_l2);
    const double oum = testing::order(errors[g - 1].velocity_max, errors[g].velocity_max);
    const double op2 = testing::order(errors[g - 1].pressure_l2, errors[g].pressure_l2);
    if (rank() == 0) std::printf("manufactured orders: u L2 %.3f max %.3f | p L2 %.3f\n", ou2, oum, op2);
    EXPECT_GE(ou2, 1.9);
    EXPECT_GE(oum, 1.9);
    EXPECT_GE(op2, 1.8);
  }
}

} // namespace
} // namespace ibvalve::fluid
