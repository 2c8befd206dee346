#include "fluid/solid_cells.hpp"

namespace ibvalve::fluid {

namespace {
template <class F>
void for_owned_faces(const StaggeredGrid& grid, int d, F&& f)
{
  for (PetscInt k = grid.begin(2); k < grid.face_end(d, 2); ++k)
    for (PetscInt j = grid.begin(1); j < grid.face_end(d, 1); ++j)
      for (PetscInt i = grid.begin(0); i < grid.face_end(d, 0); ++i) f(Index3{i, j, k});
}
} // namespace

SolidCells::SolidCells(const StaggeredGrid& grid, const BoundaryConditions& bc)
    : grid_(grid), region_(bc.solid())
{
  if (!region_) return;
  const petsc::OwnedVec local = grid.create_local();
  StagArray a(grid, local, true);
  const PetscScalar* first = &a(grid.ghost_begin(0), grid.ghost_begin(1), grid.ghost_begin(2), 0);
  auto offset = [&](const Index3& idx, PetscInt slot) {
    return static_cast<PetscInt>(&a(idx[0], idx[1], idx[2], slot) - first);
  };
  for (int d = 0; d < 3; ++d)
    for_owned_faces(grid, d, [&](const Index3& idx) {
      if (face(d, idx)) {
        blocked_faces_.push_back(offset(idx, grid.face_slot(d)));
        return;
      }
      for (int e = 0; e < 3; ++e) {
        if (e == d) continue;
        for (int sign : {-1, 1})
          if (wall_beyond(d, idx, e, sign)) wall_ghosts_.push_back({d, idx, e});
      }
    });
  for (PetscInt k = grid.begin(2); k < grid.begin(2) + grid.count(2); ++k)
    for (PetscInt j = grid.begin(1); j < grid.begin(1) + grid.count(1); ++j)
      for (PetscInt i = grid.begin(0); i < grid.begin(0) + grid.count(0); ++i)
        if (cell({i, j, k})) blocked_cells_.push_back(offset({i, j, k}, grid.pressure_slot()));
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

void SolidCells::zero(Vec local, const std::vector<PetscInt>& offsets) const
{
  if (offsets.empty()) return;
  StagArray a(grid_, local);
  PetscScalar* first = &a(grid_.ghost_begin(0), grid_.ghost_begin(1), grid_.ghost_begin(2), 0);
  for (PetscInt n : offsets) first[n] = 0.0;
}

void SolidCells::zero_faces(Vec local) const
{
  zero(local, blocked_faces_);
}

void SolidCells::zero_rows(Vec local) const
{
  zero(local, blocked_faces_);
  zero(local, blocked_cells_);
}

} // namespace ibvalve::fluid
