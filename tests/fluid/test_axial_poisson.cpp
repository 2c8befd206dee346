// The exact pressure Poisson solve for blocked cells that are the same in every z-plane
// (fluid/axial_poisson.hpp). Specification:
//  - a tube along z held as a wall, open (traction) at both z ends: the solve is chosen, and for a
//    random right side its normwise backward error |K phi - r| / (|K| |phi| + |r|) is at the level of
//    the rounding of an orthogonal transform and a Cholesky factor (below 1e3 machine epsilons);
//  - where the separation does not hold (a sphere; a tube along x) or the operator has a null space
//    (no open end) it is not chosen, and BoomerAMG keeps the Poisson part;
//  - the Stokes step with it equals the step with BoomerAMG (-fluid_poisson_pc_type hypre) to the
//    Krylov tolerance, in no more FGMRES iterations;
//  - on 2 ranks (the test's own), the ranks sharing the modes: each factors and solves its own, and
//    together they hold every mode once.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include "fluid/krylov_stokes.hpp"

namespace ibvalve::fluid {
namespace {

constexpr double tube_radius = 0.7; // cm
constexpr int across = 16;          // cells across the box
constexpr double h = 2.0 * 0.9 / across;

enum class Shape { tube_along_z, tube_along_x, sphere };

struct Case {
  BoxGeometry box;
  BoundaryConditions bc;
};

/// A box 1.8 cm across and 10 cells long in z, x and y sides no-slip walls; z sides open (traction,
/// walled outside a disk reaching beyond the tube) or walls.
Case make_case(Shape shape, bool open_ends)
{
  Case c;
  c.box.cells = {across, across, 10};
  c.box.lower = {-0.9, -0.9, 0.0};
  c.box.upper = {0.9, 0.9, 10 * h};
  c.box.periodic = {false, false, false};
  for (int s = 0; s < 4; ++s) c.bc.side(s).kind = SideKind::velocity;
  for (int s = 4; s < 6; ++s) {
    c.bc.side(s).kind = open_ends ? SideKind::traction : SideKind::velocity;
    if (open_ends) c.bc.side(s).wall = [](const Real3& x) { return std::hypot(x[0], x[1]) > 0.8; };
  }
  const double middle = 5 * h;
  switch (shape) {
  case Shape::tube_along_z:
    c.bc.set_solid([](const Real3& x) { return std::hypot(x[0], x[1]) > tube_radius; });
    break;
  case Shape::tube_along_x:
    c.bc.set_solid([=](const Real3& x) { return std::hypot(x[1], x[2] - middle) > 0.4; });
    break;
  case Shape::sphere:
    c.bc.set_solid([=](const Real3& x) { return std::hypot(x[0], x[1], x[2] - middle) < 0.3; });
    break;
  }
  return c;
}

FluidSettings krylov_settings()
{
  FluidSettings settings;
  settings.solver = SolverKind::krylov;
  settings.rtol = 1e-12;
  settings.atol = 1e-14;
  settings.max_iterations = 200;
  return settings;
}

double norm_inf(Vec v)
{
  double n = 0.0;
  PETSC_CHECK(VecNorm(v, NORM_INFINITY, &n));
  return n;
}

TEST(AxialPoisson, ATubeAlongZIsSolvedToRounding)
{
  const Case c = make_case(Shape::tube_along_z, true);
  StaggeredGrid grid(PETSC_COMM_WORLD, c.box, {}, 3);
  KrylovStokesSolver solver(grid, c.bc, krylov_settings());
  solver.set_parameters({1.0, 0.04, 1e-4});
  ASSERT_NE(solver.axial_poisson(), nullptr);
  EXPECT_EQ(solver.name(), "krylov (blocked cells, axial Poisson)");
  Mat K = solver.poisson_matrix();
  petsc::OwnedVec r, phi, residual;
  PETSC_CHECK(MatCreateVecs(K, phi.out(), r.out()));
  PETSC_CHECK(VecDuplicate(r, residual.out()));
  petsc::OwnedPetscRandom random;
  PETSC_CHECK(PetscRandomCreate(PETSC_COMM_WORLD, random.out()));
  PETSC_CHECK(PetscRandomSetSeed(random, 7));
  PETSC_CHECK(PetscRandomSeed(random));
  PETSC_CHECK(VecSetRandom(r, random));
  solver.axial_poisson()->solve(r, phi);
  PETSC_CHECK(MatMult(K, phi, residual));
  PETSC_CHECK(VecAXPY(residual, -1.0, r));
  double k_norm = 0.0;
  PETSC_CHECK(MatNorm(K, NORM_INFINITY, &k_norm));
  const double backward = norm_inf(residual) / (k_norm * norm_inf(phi) + norm_inf(r));
  std::printf("tube along z: %d fluid cells a plane, %d planes; backward error %.2e\n",
              static_cast<int>(solver.axial_poisson()->plane_cells()),
              static_cast<int>(solver.axial_poisson()->planes()), backward);
  EXPECT_LT(backward, 1e3 * std::numeric_limits<double>::epsilon());

  int rank = 0, size = 1;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  const AxialPoisson& axial = *solver.axial_poisson();
  int shares[2] = {static_cast<int>(axial.mode_count()), static_cast<int>(axial.first_mode())};
  int modes = 0, next = 0;
  MPI_Allreduce(&shares[0], &modes, 1, MPI_INT, MPI_SUM, PETSC_COMM_WORLD);
  MPI_Exscan(&shares[0], &next, 1, MPI_INT, MPI_SUM, PETSC_COMM_WORLD);
  EXPECT_EQ(modes, axial.planes());
  EXPECT_EQ(shares[1], rank == 0 ? 0 : next);
  EXPECT_GE(shares[0], axial.planes() / size);
}

TEST(AxialPoisson, WhereTheSeparationFailsMultigridStays)
{
  for (const auto& [shape, open] : {std::pair{Shape::sphere, true}, std::pair{Shape::tube_along_x, true},
                                    std::pair{Shape::tube_along_z, false}}) {
    const Case c = make_case(shape, open);
    StaggeredGrid grid(PETSC_COMM_WORLD, c.box, {}, 3);
    KrylovStokesSolver solver(grid, c.bc, krylov_settings());
    solver.set_parameters({1.0, 0.04, 1e-4});
    EXPECT_EQ(solver.axial_poisson(), nullptr);
    EXPECT_EQ(solver.name(), "krylov (blocked cells)");
  }
}

/// One Stokes step of the tube with a body force along it and a pressure drop between its ends.
SolveStatistics step(const StaggeredGrid& grid, const BoundaryConditions& bc, Vec solution)
{
  KrylovStokesSolver solver(grid, bc, krylov_settings());
  solver.set_parameters({1.0, 0.04, 1e-4});
  petsc::OwnedVec rhs = grid.create_local();
  PETSC_CHECK(VecSet(rhs, 0.0));
  PETSC_CHECK(VecSet(solution, 0.0));
  {
    StagArray f(grid, rhs);
    for (PetscInt k = grid.begin(2); k < grid.face_end(2, 2); ++k)
      for (PetscInt j = grid.begin(1); j < grid.face_end(2, 1); ++j)
        for (PetscInt i = grid.begin(0); i < grid.face_end(2, 0); ++i)
          f(i, j, k, grid.face_slot(2)) = 100.0 * (1.0 + 0.3 * std::sin(double(i + 2 * j)));
  }
  solver.add_boundary_terms(rhs, 0.0, 0.0);
  return solver.solve(rhs, solution);
}

TEST(AxialPoisson, TheStokesStepEqualsTheMultigridOne)
{
  Case c = make_case(Shape::tube_along_z, true);
  c.bc.side(2, 0).pressure = [](const Real3&, double) { return 1000.0; };
  StaggeredGrid grid(PETSC_COMM_WORLD, c.box, {}, 3);
  petsc::OwnedVec axial = grid.create_local(), multigrid = grid.create_local();
  const SolveStatistics exact = step(grid, c.bc, axial);
  PETSC_CHECK(PetscOptionsSetValue(nullptr, "-fluid_poisson_pc_type", "hypre"));
  const SolveStatistics amg = step(grid, c.bc, multigrid);
  PETSC_CHECK(PetscOptionsClearValue(nullptr, "-fluid_poisson_pc_type"));
  const double scale = norm_inf(multigrid);
  PETSC_CHECK(VecAXPY(axial, -1.0, multigrid));
  const double difference = norm_inf(axial) / scale;
  std::printf("Stokes step: %d FGMRES iterations (axial) against %d (BoomerAMG); difference %.2e of the "
              "solution's largest entry\n",
              static_cast<int>(exact.iterations), static_cast<int>(amg.iterations), difference);
  EXPECT_LE(exact.iterations, amg.iterations);
  EXPECT_LT(difference, 1e-9); // both solves to rtol 1e-12: differences of the order of the tolerance
}

} // namespace
} // namespace ibvalve::fluid
