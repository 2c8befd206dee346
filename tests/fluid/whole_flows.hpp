#pragma once
// For tests that compare whole flows (1 vs 2 ranks, a restarted vs an uninterrupted run): the flows they
// run and the whole grid's fields gathered for comparison.
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include <mpi.h>

#include "fluid/navier_stokes.hpp"
#include "fluid/queries.hpp"
#include "tests/fluid/exact_solutions.hpp"

namespace ibvalve::fluid::testing {

inline int world_rank()
{
  int r = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &r);
  return r;
}

/// The ABC flow (exact_solutions.hpp) on the periodic unit cube with n^3 cells, FFT solver.
inline std::unique_ptr<NavierStokes> abc_flow(MPI_Comm comm, PetscInt n)
{
  const AbcFlow abc;
  BoxGeometry box;
  box.cells = {n, n, n};
  FluidSettings settings;
  settings.mu = abc.rho * abc.nu;
  auto fluid = std::make_unique<NavierStokes>(comm, box, BoundaryConditions::all_periodic(), settings);
  fluid->set_initial_condition([abc](const Real3& x, double t) { return abc.velocity(x, t); },
                               [abc](const Real3& x, double t) { return abc.pressure(x, t); }, 0.0);
  return fluid;
}

/// Flow into the box [0, 2] x [0, 1]^2: a smooth jet through a disk of the x = 0 side, no-slip walls on
/// the y and z sides, and a swirling body force (kept between steps); the x = 2 side is a traction side
/// (p = 0), or with `outflow_by_velocity` a velocity side carrying the jet's flux out uniformly (a closed
/// box). Krylov solver.
inline std::unique_ptr<NavierStokes> jet_in_a_box(MPI_Comm comm, Index3 cells, bool outflow_by_velocity)
{
  BoxGeometry box;
  box.upper = {2.0, 1.0, 1.0};
  box.cells = cells;
  box.periodic = {false, false, false};
  BoundaryConditions bc;
  for (int d = 1; d < 3; ++d)
    for (int upper = 0; upper < 2; ++upper) bc.side(d, upper).kind = SideKind::velocity;
  bc.side(0, 0).kind = SideKind::velocity;
  bc.side(0, 0).velocity = [](const Real3& x, double t) {
    const double r2 = (x[1] - 0.5) * (x[1] - 0.5) + (x[2] - 0.5) * (x[2] - 0.5);
    const double profile = r2 < 0.09 ? std::pow(1.0 - r2 / 0.09, 2) : 0.0;
    return Real3{profile * std::min(1.0, 20.0 * t + 0.2), 0.0, 0.0};
  };
  if (outflow_by_velocity) {
    bc.side(0, 1).kind = SideKind::velocity;
    bc.side(0, 1).velocity = [](const Real3&, double t) {
      // The jet's flux (about pi 0.09 / 3) spread over the unit side.
      return Real3{std::acos(-1.0) * 0.09 / 3.0 * std::min(1.0, 20.0 * t + 0.2), 0.0, 0.0};
    };
  } else {
    bc.side(0, 1).kind = SideKind::traction;
  }
  FluidSettings settings;
  settings.rho = 1.0;
  settings.mu = 0.02;
  settings.solver = SolverKind::krylov;
  settings.rtol = 1e-13;
  settings.atol = 1e-15;
  auto fluid = std::make_unique<NavierStokes>(comm, box, bc, settings);
  fluid->set_initial_condition([](const Real3&, double) { return Real3{0.0, 0.0, 0.0}; }, nullptr, 0.0);
  fluid->set_body_force([](const Real3& x, double) { return Real3{0.0, -(x[2] - 0.5), (x[1] - 0.5)}; }, 0.0);
  return fluid;
}

/// The whole grid's cell-centred velocity, vorticity and pressure, 7 values per cell in C order, on every
/// rank of the solver's communicator.
inline std::vector<double> gather_fields(const NavierStokes& fluid)
{
  const StaggeredGrid& grid = fluid.grid();
  const CellFields mine = cell_fields(fluid);
  const PetscInt nx = grid.cells(0), ny = grid.cells(1), nz = grid.cells(2);
  std::vector<double> all(static_cast<std::size_t>(7 * nx * ny * nz), 0.0);
  std::size_t c = 0;
  for (PetscInt k = mine.begin[2]; k < mine.begin[2] + mine.count[2]; ++k)
    for (PetscInt j = mine.begin[1]; j < mine.begin[1] + mine.count[1]; ++j)
      for (PetscInt i = mine.begin[0]; i < mine.begin[0] + mine.count[0]; ++i, ++c) {
        const auto cell = static_cast<std::size_t>((k * ny + j) * nx + i);
        for (int q = 0; q < 3; ++q) {
          all[7 * cell + q] = mine.velocity[3 * c + q];
          all[7 * cell + 3 + q] = mine.vorticity[3 * c + q];
        }
        all[7 * cell + 6] = mine.pressure[c];
      }
  // Each cell has one owner, so the sum adds zeros: the values keep their bits.
  MPI_Allreduce(MPI_IN_PLACE, all.data(), static_cast<int>(all.size()), MPI_DOUBLE, MPI_SUM, grid.comm());
  return all;
}

} // namespace ibvalve::fluid::testing
