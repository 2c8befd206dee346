#pragma once
// For tests that compare whole flows (1 vs 2 ranks, a restarted vs an uninterrupted run): the whole grid's
// cell-centred velocity, vorticity and pressure, 7 values per cell in C order, on every rank of the
// solver's communicator.
#include <vector>

#include <mpi.h>

#include "fluid/navier_stokes.hpp"
#include "fluid/queries.hpp"

namespace ibvalve::fluid::testing {

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
