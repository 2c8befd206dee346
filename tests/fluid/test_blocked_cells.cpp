// Rigid walls held by the fluid (fluid/solid_cells.hpp): the cells whose centre lies in a solid region are
// blocked. Specification:
//  - plane Poiseuille flow between walls along cell faces, driven by a body force and stepped by the
//    Navier–Stokes integrator from the exact profile, stays on it to O(h^2) (measured order 2 +- 0.25:
//    the odd ghost -u_0 is a second-order wall condition, and the explicit and implicit halves of
//    Crank–Nicolson see the same wall);
//  - Poiseuille flow in a round pipe whose wall is a staircase of cell faces: the flux converges at first
//    order in h (the staircase moves the wall by O(h)), measured over three grids;
//  - no velocity on a blocked face, no divergence in any cell, to solver tolerance;
//  - a new step length taken in place (KrylovStokesSolver::change_step) gives the matrix and the solution a
//    solver built afresh at that step gives, bit for bit, with and without blocked cells;
//  - 1 rank and 2 ranks agree to solver tolerance.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <utility>

#include "fluid/krylov_stokes.hpp"
#include "fluid/navier_stokes.hpp"
#include "fluid/queries.hpp"

namespace ibvalve::fluid {
namespace {

constexpr double mu = 0.04;      // dyn s/cm^2 (the pipe)
constexpr double drive = 1.0;    // body force, dyn/cm^3
constexpr double half_gap = 0.5; // channel: walls at y = +-0.5 cm
constexpr double radius = 0.7;   // pipe radius, cm

double global_max(MPI_Comm comm, double x)
{
  MPI_Allreduce(MPI_IN_PLACE, &x, 1, MPI_DOUBLE, MPI_MAX, comm);
  return x;
}

/// The channel: x and z periodic, y sides no-slip walls a cell and more beyond the blocked cells.
struct ChannelResult {
  double max_error = 0.0;        // max |u_x - exact| over fluid faces, relative to the centre speed
  double blocked_velocity = 0.0; // max |u| on blocked faces
  double divergence = 0.0;
};

ChannelResult run_channel(MPI_Comm comm, int cells_across_gap)
{
  const double h = 2.0 * half_gap / cells_across_gap;
  BoxGeometry box;
  const int blocked_rows = 2; // blocked cells beside each wall
  box.cells = {8, cells_across_gap + 2 * blocked_rows, 8};
  box.lower = {0.0, -half_gap - blocked_rows * h, 0.0};
  box.upper = {8 * h, half_gap + blocked_rows * h, 8 * h};
  box.periodic = {true, false, true};
  BoundaryConditions bc;
  bc.side(1, 0).kind = bc.side(1, 1).kind = SideKind::velocity;
  bc.set_solid([](const Real3& x) { return std::abs(x[1]) > half_gap; });
  FluidSettings settings;
  settings.rho = 1.0;
  // A viscous fluid (1 cm^2/s): the channel's slowest mode decays in (2 a)^2 / (pi^2 nu) = 0.1 s, so 100
  // steps of 0.01 s reach the discrete steady state to 1e-4 of the start's O(h^2) mismatch.
  const double viscosity = 1.0;
  settings.mu = viscosity;
  settings.solver = SolverKind::krylov;
  settings.rtol = 1e-12;
  settings.atol = 1e-14;
  NavierStokes fluid(comm, box, bc, settings);
  const double centre_speed = drive * half_gap * half_gap / (2.0 * viscosity);
  auto exact = [&](const Real3& x, double) {
    const double y = x[1];
    return Real3{std::abs(y) < half_gap ? drive / (2.0 * viscosity) * (half_gap * half_gap - y * y) : 0.0,
                 0.0, 0.0};
  };
  fluid.set_initial_condition(exact, nullptr, 0.0);
  fluid.set_body_force([](const Real3&, double) { return Real3{drive, 0.0, 0.0}; }, 0.0);
  for (int n = 0; n < 100; ++n) fluid.step(0.01);

  ChannelResult result;
  const StaggeredGrid& grid = fluid.grid();
  const SolidCells solid(grid, bc);
  StagArray u(grid, fluid.state(), true);
  for (int d = 0; d < 3; ++d)
    for (PetscInt k = grid.begin(2); k < grid.face_end(d, 2); ++k)
      for (PetscInt j = grid.begin(1); j < grid.face_end(d, 1); ++j)
        for (PetscInt i = grid.begin(0); i < grid.face_end(d, 0); ++i) {
          const double value = u(i, j, k, grid.face_slot(d));
          if (solid.face(d, {i, j, k}))
            result.blocked_velocity = std::max(result.blocked_velocity, std::abs(value));
          else
            result.max_error =
                std::max(result.max_error,
                         std::abs(value - exact(grid.face_position(d, i, j, k), 0.0)[d]) / centre_speed);
        }
  result.max_error = global_max(comm, result.max_error);
  result.blocked_velocity = global_max(comm, result.blocked_velocity) / centre_speed;
  result.divergence = max_divergence(fluid) * h / centre_speed;
  return result;
}

TEST(BlockedCells, ChannelWallsAlongFacesAreSecondOrder)
{
  const ChannelResult coarse = run_channel(PETSC_COMM_WORLD, 8);
  const ChannelResult fine = run_channel(PETSC_COMM_WORLD, 16);
  const double order = std::log2(coarse.max_error / fine.max_error);
  std::printf("channel: max error / centre speed %.3e (8 cells across), %.3e (16): order %.2f\n",
              coarse.max_error, fine.max_error, order);
  EXPECT_NEAR(order, 2.0, 0.25);
  EXPECT_LT(fine.max_error, 0.01);
  for (const ChannelResult& r : {coarse, fine}) {
    EXPECT_LT(r.blocked_velocity, 1e-12);
    EXPECT_LT(r.divergence, 1e-9);
  }
}

/// Steady Stokes flow in the pipe r < radius along z (periodic), the box's x and y sides no-slip walls
/// beyond the blocked cells: mu L u - G p = -f, solved as the Stokes step with rho/dt -> 0 and mu/2 -> mu.
/// Returns the flux through the plane z = 0 (mL/s).
double pipe_flux(MPI_Comm comm, int cells_across)
{
  const double extent = radius + 2.0 * (2.0 * radius / cells_across); // two cells of wall beyond the pipe
  BoxGeometry box;
  const double h = 2.0 * extent / (cells_across + 4);
  box.cells = {cells_across + 4, cells_across + 4, 8};
  box.lower = {-extent, -extent, 0.0};
  box.upper = {extent, extent, 8 * h};
  box.periodic = {false, false, true};
  BoundaryConditions bc;
  for (int s = 0; s < 4; ++s) bc.side(s).kind = SideKind::velocity;
  bc.set_solid([](const Real3& x) { return std::hypot(x[0], x[1]) > radius; });
  FluidSettings settings;
  settings.solver = SolverKind::krylov;
  settings.subsolver = SubsolverKind::fft; // blocked cells: the solver takes BoomerAMG for the Poisson part
  settings.rtol = 1e-11;
  settings.atol = 1e-14;
  settings.max_iterations = 500;
  StaggeredGrid grid(comm, box, {}, 3);
  KrylovStokesSolver solver(grid, bc, settings);
  solver.set_parameters({1.0, 2.0 * mu, 1e12});
  EXPECT_EQ(solver.transforms(), nullptr);
  petsc::OwnedVec rhs = grid.create_local(), solution = grid.create_local();
  PETSC_CHECK(VecSet(rhs, 0.0));
  PETSC_CHECK(VecSet(solution, 0.0));
  {
    StagArray r(grid, rhs);
    for (PetscInt k = grid.begin(2); k < grid.face_end(2, 2); ++k)
      for (PetscInt j = grid.begin(1); j < grid.face_end(2, 1); ++j)
        for (PetscInt i = grid.begin(0); i < grid.face_end(2, 0); ++i) r(i, j, k, grid.face_slot(2)) = drive;
  }
  solver.add_boundary_terms(rhs, 0.0, 0.0);
  const SolveStatistics stats = solver.solve(rhs, solution);
  EXPECT_LT(stats.iterations, 500);
  double flux = 0.0, blocked = 0.0;
  {
    StagArray u(grid, solution, true);
    const SolidCells& solid = solver.solid();
    if (grid.begin(2) == 0)
      for (PetscInt j = grid.begin(1); j < grid.begin(1) + grid.count(1); ++j)
        for (PetscInt i = grid.begin(0); i < grid.begin(0) + grid.count(0); ++i)
          flux += u(i, j, 0, grid.face_slot(2)) * h * h;
    for (int d = 0; d < 3; ++d)
      for (PetscInt k = grid.begin(2); k < grid.face_end(d, 2); ++k)
        for (PetscInt j = grid.begin(1); j < grid.face_end(d, 1); ++j)
          for (PetscInt i = grid.begin(0); i < grid.face_end(d, 0); ++i)
            if (solid.face(d, {i, j, k}))
              blocked = std::max(blocked, std::abs(u(i, j, k, grid.face_slot(d))));
  }
  MPI_Allreduce(MPI_IN_PLACE, &flux, 1, MPI_DOUBLE, MPI_SUM, comm);
  EXPECT_LT(global_max(comm, blocked), 1e-12);
  std::printf("pipe, %d cells across: flux %.10e mL/s, %d FGMRES iterations\n", cells_across, flux,
              static_cast<int>(stats.iterations));
  return flux;
}

TEST(BlockedCells, PipeStaircaseFluxConvergesAtFirstOrder)
{
  // Hagen–Poiseuille: Q = pi f R^4 / (8 mu).
  const double exact = std::numbers::pi * drive * std::pow(radius, 4) / (8.0 * mu);
  double errors[3];
  const int across[3] = {14, 28, 56};
  for (int n = 0; n < 3; ++n) errors[n] = std::abs(pipe_flux(PETSC_COMM_WORLD, across[n]) - exact) / exact;
  const double order = std::log2(errors[0] / errors[2]) / 2.0;
  std::printf("pipe: relative flux errors %.3e, %.3e, %.3e: mean order %.2f\n", errors[0], errors[1],
              errors[2], order);
  EXPECT_GT(order, 0.7);
  EXPECT_LT(errors[2], errors[0]);
}

/// The system at dt = 2e-3 reached from 1e-3 in place, against one built at 2e-3: difference of the
/// matrices (max |entry|) and of the solutions (max |entry|) for the same right side.
std::pair<double, double> in_place_against_fresh(bool blocked, SubsolverKind subsolver)
{
  BoxGeometry box;
  box.cells = {12, 10, 14};
  box.lower = {-1.0, -1.0, 0.0};
  box.upper = {1.0, 1.0, 2.0};
  box.periodic = {false, false, false};
  BoundaryConditions bc;
  for (int s = 0; s < 4; ++s) bc.side(s).kind = SideKind::velocity;
  bc.side(2, 0).kind = bc.side(2, 1).kind = SideKind::traction;
  bc.side(2, 0).pressure = [](const Real3&, double) { return 50.0; };
  if (blocked) bc.set_solid([](const Real3& x) { return std::hypot(x[0], x[1]) > radius; });
  FluidSettings settings;
  settings.solver = SolverKind::krylov;
  settings.subsolver = subsolver;
  settings.mu = mu;
  settings.rtol = 1e-10;
  StaggeredGrid grid(PETSC_COMM_WORLD, box, {}, 3);
  KrylovStokesSolver moved(grid, bc, settings), fresh(grid, bc, settings);
  moved.set_parameters({1.0, mu, 1e-3});
  moved.set_parameters({1.0, mu, 2e-3});
  fresh.set_parameters({1.0, mu, 2e-3});
  petsc::OwnedMat difference;
  PETSC_CHECK(MatDuplicate(moved.matrix(), MAT_COPY_VALUES, difference.out()));
  PETSC_CHECK(MatAXPY(difference, -1.0, fresh.matrix(), DIFFERENT_NONZERO_PATTERN));
  PetscReal matrix_difference = 0.0;
  PETSC_CHECK(MatNorm(difference, NORM_INFINITY, &matrix_difference));
  petsc::OwnedVec rhs = grid.create_local(), a = grid.create_local(), b = grid.create_local();
  {
    StagArray r(grid, rhs);
    for (int d = 0; d < 3; ++d)
      for (PetscInt k = grid.begin(2); k < grid.face_end(d, 2); ++k)
        for (PetscInt j = grid.begin(1); j < grid.face_end(d, 1); ++j)
          for (PetscInt i = grid.begin(0); i < grid.face_end(d, 0); ++i)
            r(i, j, k, grid.face_slot(d)) = std::sin(1.0 + i + 2.0 * j + 3.0 * k + d);
  }
  for (KrylovStokesSolver* solver : {&moved, &fresh}) solver->add_boundary_terms(rhs, 0.0, 0.0);
  PETSC_CHECK(VecSet(a, 0.0));
  PETSC_CHECK(VecSet(b, 0.0));
  moved.solve(rhs, a);
  fresh.solve(rhs, b);
  PETSC_CHECK(VecAXPY(a, -1.0, b));
  PetscReal solution_difference = 0.0;
  PETSC_CHECK(VecNorm(a, NORM_INFINITY, &solution_difference));
  return {matrix_difference, global_max(PETSC_COMM_WORLD, solution_difference)};
}

TEST(BlockedCells, ANewStepInPlaceEqualsAFreshBuild)
{
  for (bool blocked : {false, true})
    for (SubsolverKind subsolver : {SubsolverKind::fft, SubsolverKind::amg}) {
      const auto [matrix, solution] = in_place_against_fresh(blocked, subsolver);
      std::printf("new step in place vs fresh (%s, %s sub-solves): matrices differ by %g, solutions by %g\n",
                  blocked ? "blocked cells" : "open box", subsolver == SubsolverKind::fft ? "fft" : "amg",
                  matrix, solution);
      EXPECT_EQ(matrix, 0.0);
      EXPECT_EQ(solution, 0.0);
    }
}

TEST(BlockedCells, OneAndTwoRanksAgree)
{
  int size = 1, rank = 0;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  ASSERT_EQ(size, 2) << "this test runs on 2 ranks";
  const double two = pipe_flux(PETSC_COMM_WORLD, 20);
  const ChannelResult channel_two = run_channel(PETSC_COMM_WORLD, 8);
  MPI_Comm alone;
  MPI_Comm_split(PETSC_COMM_WORLD, rank, 0, &alone);
  const double one = pipe_flux(alone, 20);
  const ChannelResult channel_one = run_channel(alone, 8);
  MPI_Comm_free(&alone);
  std::printf("1 rank vs 2 ranks: pipe flux %.12e / %.12e; channel error %.12e / %.12e\n", one, two,
              channel_one.max_error, channel_two.max_error);
  EXPECT_NEAR(one, two, 1e-9 * std::abs(one));
  EXPECT_NEAR(channel_one.max_error, channel_two.max_error, 1e-9);
}

} // namespace
} // namespace ibvalve::fluid
