#include "fluid/grid.hpp"

#include <stdexcept>
#include <string>

#include "io/petsc_check.hpp"

namespace ibvalve::fluid {

StaggeredGrid::StaggeredGrid(MPI_Comm comm, const BoxGeometry& box, const Decomposition& decomposition,
                             PetscInt stencil_width)
    : comm_(comm), box_(box)
{
  for (int d = 0; d < 3; ++d) {
    if (box.cells[d] < 2) throw std::invalid_argument("fluid grid: at least 2 cells per direction");
    if (!(box.length(d) > 0.0)) throw std::invalid_argument("fluid grid: the box must have positive extent");
    h_[d] = box.spacing(d);
  }
  int size = 1;
  MPI_Comm_size(comm, &size);
  auto boundary = [&](int d) { return box.periodic[d] ? DM_BOUNDARY_PERIODIC : DM_BOUNDARY_GHOSTED; };
  PetscInt ranks_x = PETSC_DECIDE, ranks_y = PETSC_DECIDE, ranks_z = PETSC_DECIDE;
  const PetscInt* lz = nullptr;
  if (decomposition.slabs_in_z) {
    ranks_x = 1;
    ranks_y = 1;
    ranks_z = size;
    if (!decomposition.z_ownership.empty()) {
      if (static_cast<int>(decomposition.z_ownership.size()) != size)
        throw std::invalid_argument("fluid grid: z ownership needs one entry per rank");
      lz = decomposition.z_ownership.data();
    }
  }
  PETSC_CHECK(DMStagCreate3d(comm, boundary(0), boundary(1), boundary(2), box.cells[0], box.cells[1],
                             box.cells[2], ranks_x, ranks_y, ranks_z, 0, 0, 1, 1, DMSTAG_STENCIL_BOX,
                             stencil_width, nullptr, nullptr, lz, dm_.out()));
  PETSC_CHECK(DMSetUp(dm_));
  PETSC_CHECK(DMStagSetUniformCoordinatesProduct(dm_, box.lower[0], box.upper[0], box.lower[1], box.upper[1],
                                                 box.lower[2], box.upper[2]));
  PetscInt extra[3];
  PETSC_CHECK(DMStagGetCorners(dm_, &begin_[0], &begin_[1], &begin_[2], &count_[0], &count_[1], &count_[2],
                               &extra[0], &extra[1], &extra[2]));
  PETSC_CHECK(DMStagGetGhostCorners(dm_, &ghost_begin_[0], &ghost_begin_[1], &ghost_begin_[2],
                                    &ghost_count_[0], &ghost_count_[1], &ghost_count_[2]));
  PetscBool last[3];
  PETSC_CHECK(DMStagGetIsLastRank(dm_, &last[0], &last[1], &last[2]));
  for (int d = 0; d < 3; ++d) owns_upper_[d] = last[d] == PETSC_TRUE;
  const DMStagStencilLocation faces[3] = {DMSTAG_LEFT, DMSTAG_DOWN, DMSTAG_BACK};
  for (int d = 0; d < 3; ++d) PETSC_CHECK(DMStagGetLocationSlot(dm_, faces[d], 0, &face_slot_[d]));
  PETSC_CHECK(DMStagGetLocationSlot(dm_, DMSTAG_ELEMENT, 0, &pressure_slot_));
}

petsc::OwnedVec StaggeredGrid::create_global() const
{
  petsc::OwnedVec v;
  PETSC_CHECK(DMCreateGlobalVector(dm_, v.out()));
  PETSC_CHECK(VecZeroEntries(v));
  return v;
}

petsc::OwnedVec StaggeredGrid::create_local() const
{
  petsc::OwnedVec v;
  PETSC_CHECK(DMCreateLocalVector(dm_, v.out()));
  PETSC_CHECK(VecZeroEntries(v));
  return v;
}

void StaggeredGrid::global_to_local(Vec global, Vec local) const
{
  PETSC_CHECK(DMGlobalToLocalBegin(dm_, global, INSERT_VALUES, local));
  PETSC_CHECK(DMGlobalToLocalEnd(dm_, global, INSERT_VALUES, local));
}

StagArray::StagArray(const StaggeredGrid& grid, Vec local, bool read_only) : v_(local), read_only_(read_only)
{
  for (int d = 0; d < 3; ++d) {
    g_[d] = grid.ghost_begin(d);
    n_[d] = grid.ghost_end(d) - grid.ghost_begin(d);
  }
  PETSC_CHECK(DMStagGetEntriesPerElement(grid.dm(), &dof_));
  stride_y_ = dof_ * n_[0];
  PetscInt size = 0;
  PETSC_CHECK(VecGetLocalSize(local, &size));
  if (size != dof_ * n_[0] * n_[1] * n_[2])
    throw std::invalid_argument("fluid: StagArray needs a local (ghosted) vector of the grid");
  if (read_only)
    PETSC_CHECK(VecGetArrayRead(local, const_cast<const PetscScalar**>(&data_)));
  else
    PETSC_CHECK(VecGetArray(local, &data_));
}

StagArray::~StagArray()
{
  if (read_only_)
    VecRestoreArrayRead(v_, const_cast<const PetscScalar**>(&data_));
  else
    VecRestoreArray(v_, &data_);
}

} // namespace ibvalve::fluid
