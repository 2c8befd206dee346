// A traction side that is a wall in part (fluid/boundary.hpp, BoundarySide::wall): pressure-driven flow
// enters through a disk of the lower z side and leaves through a disk of the upper z side; the rest of
// both sides and the four x, y sides are no-slip walls. Specification:
//  - the normal velocity on every walled boundary face is zero to solver tolerance (an identity row of
//    the Stokes system), and flow does cross the open disks;
//  - the volume entering equals the volume leaving (the discrete divergence is zero to solver tolerance);
//  - a walled part is a constraint: for the same pressures less flow crosses than with the whole sides
//    open (Stokes flow minimises dissipation, Helmholtz's theorem; a constraint cannot add flux);
//  - 1 rank and 2 ranks agree to solver tolerance.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "fluid/navier_stokes.hpp"
#include "fluid/queries.hpp"

namespace ibvalve::fluid {
namespace {

constexpr double lumen = 0.5; // disk radius, cm
constexpr double inlet_pressure = 100.0;

struct Duct {
  std::unique_ptr<NavierStokes> fluid;
  double wall_normal_velocity = 0.0; // largest |u_n| on walled boundary faces (this rank)
  double open_normal_velocity = 0.0; // largest |u_n| on open boundary faces (this rank)
};

Duct run_duct(MPI_Comm comm, bool walled, int steps)
{
  BoxGeometry box;
  box.lower = {-1.0, -1.0, 0.0};
  box.upper = {1.0, 1.0, 3.0};
  box.cells = {12, 12, 18};
  box.periodic = {false, false, false};
  BoundaryConditions bc;
  for (int s = 0; s < 4; ++s) bc.side(s).kind = SideKind::velocity;
  auto outside_lumen = [](const Real3& x) { return std::hypot(x[0], x[1]) >= lumen; };
  for (int upper = 0; upper < 2; ++upper) {
    BoundarySide& side = bc.side(2, upper);
    side.kind = SideKind::traction;
    if (walled) side.wall = outside_lumen;
  }
  bc.side(2, 0).pressure = [](const Real3&, double) { return inlet_pressure; };
  FluidSettings settings;
  settings.rho = 1.0;
  settings.mu = 0.04;
  settings.solver = SolverKind::krylov;
  settings.subsolver = SubsolverKind::fft;
  settings.rtol = 1e-12;
  settings.atol = 1e-13;
  Duct duct;
  duct.fluid = std::make_unique<NavierStokes>(comm, box, bc, settings);
  duct.fluid->set_initial_condition([](const Real3&, double) { return Real3{0.0, 0.0, 0.0}; }, nullptr, 0.0);
  for (int n = 0; n < steps; ++n) duct.fluid->step(2e-3);

  const StaggeredGrid& grid = duct.fluid->grid();
  StagArray u(grid, duct.fluid->state(), true);
  for (int upper = 0; upper < 2; ++upper) {
    if (upper ? !grid.owns_upper(2) : !grid.owns_lower(2)) continue;
    const PetscInt k = upper ? grid.cells(2) : 0;
    for (PetscInt j = grid.begin(1); j < grid.begin(1) + grid.count(1); ++j)
      for (PetscInt i = grid.begin(0); i < grid.begin(0) + grid.count(0); ++i) {
        const double w = std::abs(u(i, j, k, grid.face_slot(2)));
        if (outside_lumen(grid.face_position(2, i, j, k)))
          duct.wall_normal_velocity = std::max(duct.wall_normal_velocity, w);
        else
          duct.open_normal_velocity = std::max(duct.open_normal_velocity, w);
      }
  }
  return duct;
}

double global_max(double x)
{
  MPI_Allreduce(MPI_IN_PLACE, &x, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD);
  return x;
}

TEST(WalledTractionSides, FlowCrossesOnlyTheOpenPartAndIsConserved)
{
  const Duct duct = run_duct(PETSC_COMM_WORLD, true, 10);
  const NavierStokes& fluid = *duct.fluid;
  const double open = global_max(duct.open_normal_velocity);
  EXPECT_LT(global_max(duct.wall_normal_velocity), 1e-8 * open);
  EXPECT_GT(open, 1.0);

  const Real3 centre{0.0, 0.0, 0.0};
  const double in = volume_flux(fluid, PlaneRegion::disk(2, 0.0, centre, 2.0));
  const double out = volume_flux(fluid, PlaneRegion::disk(2, 3.0, centre, 2.0));
  const double mid = volume_flux(fluid, PlaneRegion::disk(2, 1.5, centre, 2.0));
  std::printf("walled sides: flux in %.6e, mid %.6e, out %.6e mL/s; max u_n open %.3e; max |D u| %.2e\n", in,
              mid, out, open, max_divergence(fluid));
  EXPECT_GT(in, 0.0);
  EXPECT_NEAR(out, in, 1e-9 * in);
  EXPECT_NEAR(mid, in, 1e-9 * in);
  EXPECT_LT(max_divergence(fluid) * 0.1, 1e-9 * open); // |D u| h relative to the velocity
}

TEST(WalledTractionSides, WallsAroundTheLumenReduceTheFlux)
{
  const Duct walled = run_duct(PETSC_COMM_WORLD, true, 10);
  const Duct open = run_duct(PETSC_COMM_WORLD, false, 10);
  const Real3 centre{0.0, 0.0, 0.0};
  const double q_walled = volume_flux(*walled.fluid, PlaneRegion::disk(2, 1.5, centre, 2.0));
  const double q_open = volume_flux(*open.fluid, PlaneRegion::disk(2, 1.5, centre, 2.0));
  std::printf("flux with walls around the lumen %.4e, whole sides open %.4e mL/s\n", q_walled, q_open);
  EXPECT_GT(q_walled, 0.0);
  EXPECT_LT(q_walled, q_open);
}

TEST(WalledTractionSides, OneAndTwoRanksAgree)
{
  int size = 1, rank = 0;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  ASSERT_EQ(size, 2) << "this test runs on 2 ranks";
  const Real3 centre{0.0, 0.0, 0.0};
  const Duct two = run_duct(PETSC_COMM_WORLD, true, 5);
  const double q_two = volume_flux(*two.fluid, PlaneRegion::disk(2, 1.5, centre, 2.0));
  const double p_two = pressure_at(*two.fluid, Real3{0.1, 0.2, 1.0});
  MPI_Comm alone;
  MPI_Comm_split(PETSC_COMM_WORLD, rank, 0, &alone);
  const Duct one = run_duct(alone, true, 5);
  const double q_one = volume_flux(*one.fluid, PlaneRegion::disk(2, 1.5, centre, 2.0));
  const double p_one = pressure_at(*one.fluid, Real3{0.1, 0.2, 1.0});
  std::printf("1 rank vs 2 ranks: flux %.12e / %.12e, pressure %.12e / %.12e\n", q_one, q_two, p_one, p_two);
  EXPECT_NEAR(q_one, q_two, 1e-9 * std::abs(q_one));
  EXPECT_NEAR(p_one, p_two, 1e-9 * inlet_pressure);
  MPI_Comm_free(&alone);
}

} // namespace
} // namespace ibvalve::fluid
