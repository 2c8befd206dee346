#include "fluid/solid_cells.hpp"

#include <mpi.h>

#include "io/petsc_check.hpp"

namespace ibvalve::fluid {

SolidCells::SolidCells(const StaggeredGrid& grid, const BoundaryConditions& bc)
    : grid_(grid), region_(bc.solid())
{
}

bool SolidCells::cell(Index3 idx) const
{
  if (!region_) return false;
  for (int d = 0; d < 3; ++d) {
    const PetscInt n = grid_.cells(d);
    if (grid_.periodic(d))
      idx[d] = ((idx[d] % n) + n) % n;
    else if (idx[d] < 0 || idx[d] >= n)
      return false;
  }
  return region_(grid_.cell_center(idx[0], idx[1], idx[2]));
}

bool SolidCells::face(int d, const Index3& idx) const
{
  if (!region_) return false;
  Index3 below = idx;
  below[d] -= 1;
  return cell(idx) || cell(below);
}

bool SolidCells::wall_beyond(int d, const Index3& idx, int e, int sign) const
{
  if (!region_) return false;
  Index3 a = idx;
  a[e] += sign;
  Index3 b = a;
  b[d] -= 1;
  return cell(a) && cell(b);
}

namespace {
template <class F>
void for_owned_faces(const StaggeredGrid& grid, int d, F&& f)
{
  for (PetscInt k = grid.begin(2); k < grid.face_end(d, 2); ++k)
    for (PetscInt j = grid.begin(1); j < grid.face_end(d, 1); ++j)
      for (PetscInt i = grid.begin(0); i < grid.face_end(d, 0); ++i) f(Index3{i, j, k});
}
} // namespace

std::vector<WallGhost> SolidCells::wall_ghosts() const
{
  std::vector<WallGhost> ghosts;
  if (!region_) return ghosts;
  for (int d = 0; d < 3; ++d)
    for_owned_faces(grid_, d, [&](const Index3& idx) {
      if (face(d, idx)) return;
      for (int e = 0; e < 3; ++e) {
        if (e == d) continue;
        for (int sign : {-1, 1})
          if (wall_beyond(d, idx, e, sign)) ghosts.push_back({d, idx, e});
      }
    });
  return ghosts;
}

PetscInt SolidCells::blocked_cells() const
{
  PetscInt count = 0;
  if (region_)
    for (PetscInt k = grid_.begin(2); k < grid_.begin(2) + grid_.count(2); ++k)
      for (PetscInt j = grid_.begin(1); j < grid_.begin(1) + grid_.count(1); ++j)
        for (PetscInt i = grid_.begin(0); i < grid_.begin(0) + grid_.count(0); ++i)
          if (cell({i, j, k})) ++count;
  PETSC_CHECK(MPI_Allreduce(MPI_IN_PLACE, &count, 1, MPIU_INT, MPI_SUM, grid_.comm()));
  return count;
}

void zero_blocked_faces(const SolidCells& solid, const StaggeredGrid& grid, Vec local)
{
  if (solid.empty()) return;
  StagArray a(grid, local);
  for (int d = 0; d < 3; ++d)
    for_owned_faces(grid, d, [&](const Index3& idx) {
      if (solid.face(d, idx)) a(idx[0], idx[1], idx[2], grid.face_slot(d)) = 0.0;
    });
}

} // namespace ibvalve::fluid
