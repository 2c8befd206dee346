// Queries on 2 ranks: point values interpolate linear fields exactly anywhere (also across the
// ranks' seam), and the global norms of a Taylor–Green field match their integrals to O(h^2).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "fluid/queries.hpp"

namespace ibvalve::fluid {
namespace {

TEST(Queries, PointValuesReproduceLinearFieldsEverywhere)
{
  BoxGeometry box;
  box.lower = {-1.0, 0.0, 0.5};
  box.upper = {1.0, 1.0, 2.0};
  box.cells = {12, 10, 14};
  box.periodic = {false, false, false};
  BoundaryConditions bc;
  for (int s = 0; s < 6; ++s) bc.side(s).kind = SideKind::velocity;
  FluidSettings settings;
  settings.solver = SolverKind::krylov;
  NavierStokes fluid(PETSC_COMM_WORLD, box, bc, settings);
  auto u = [](const Real3& x, double) {
    return Real3{1.0 + 2.0 * x[0] - x[1] + 0.5 * x[2], -3.0 + x[0] + 4.0 * x[1],
                 0.25 * x[2] - x[0] * 0.0 + x[1]};
  };
  auto p = [](const Real3& x, double) { return 7.0 - x[0] + 2.0 * x[1] - 3.0 * x[2]; };
  fluid.set_initial_condition(u, p, 0.0);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double worst_u = 0.0, worst_p = 0.0;
  for (int n = 0; n < 200; ++n) {
    // Inside the box by one cell, where no wall ghost enters the stencil.
    Real3 x;
    for (int d = 0; d < 3; ++d)
      x[d] = box.lower[d] + box.spacing(d) * (1.0 + unit(random) * (box.cells[d] - 2));
    const Real3 v = velocity_at(fluid, x), exact = u(x, 0.0);
    for (int d = 0; d < 3; ++d) worst_u = std::max(worst_u, std::abs(v[d] - exact[d]));
    worst_p = std::max(worst_p, std::abs(pressure_at(fluid, x) - p(x, 0.0)));
  }
  EXPECT_LT(worst_u, 1e-12);
  EXPECT_LT(worst_p, 1e-12);
}

TEST(Queries, EnergyEnstrophyAndSpeedOfATaylorGreenField)
{
  // u = (sin x cos y, -cos x sin y, 0) on [0, 2 pi]^2 x [0, 1]: 1/2 int |u|^2 = pi^2 (volume 4 pi^2,
  // mean |u|^2 = 1/2), omega_z = 2 sin x sin y so 1/2 int omega^2 = 2 pi^2, max |u| = 1.
  const double pi = std::numbers::pi;
  BoxGeometry box;
  box.upper = {2.0 * pi, 2.0 * pi, 1.0};
  box.cells = {32, 32, 4};
  FluidSettings settings;
  NavierStokes fluid(PETSC_COMM_WORLD, box, BoundaryConditions::all_periodic(), settings);
  fluid.set_initial_condition(
      [](const Real3& x, double) {
        return Real3{std::sin(x[0]) * std::cos(x[1]), -std::cos(x[0]) * std::sin(x[1]), 0.0};
      },
      nullptr, 0.0);
  const double h = box.spacing(0);
  EXPECT_NEAR(kinetic_energy(fluid), pi * pi, 1e-12);          // exact: the face sums of sin^2 are exact
  EXPECT_NEAR(enstrophy(fluid) / (2.0 * pi * pi), 1.0, h * h); // edge curl and cell averages: O(h^2)
  EXPECT_NEAR(max_velocity_magnitude(fluid), 1.0, h * h);
  EXPECT_LT(max_divergence(fluid), 1e-12);
}

} // namespace
} // namespace ibvalve::fluid
