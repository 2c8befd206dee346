#pragma once
// The staggered (MAC) grid: a box of Nx x Ny x Nz uniform cells split over MPI ranks by a PETSc DMStag.
//
// Unknowns (Harlow & Welch 1965): the velocity component d lives on the faces normal to d, the
// pressure at cell centres. One DMStag with one dof per face and one per element holds both, so the
// coupled Stokes system is one PETSc vector. In a local (ghosted) array a(i, j, k, slot) (StagArray), slot
// face_slot(d) of element (i,j,k) is the face at its low side in direction d: the x-face at
// (x0 + i hx, y0 + (j+1/2) hy, z0 + (k+1/2) hz), and so on; slot pressure_slot() is the cell centre.
// Indices are global. A non-periodic direction has N+1 faces (0..N); the last rank in that direction
// owns the extra face N (DMStag's "extra" point).
#include <array>
#include <cstddef>
#include <vector>

#include <petscdmstag.h>

#include "io/petsc_handle.hpp"

namespace ibvalve::fluid {

using Index3 = std::array<PetscInt, 3>;
using Real3 = std::array<double, 3>;

/// The box and how it is cut into cells.
struct BoxGeometry {
  Real3 lower{0.0, 0.0, 0.0};
  Real3 upper{1.0, 1.0, 1.0};
  Index3 cells{16, 16, 16};
  std::array<bool, 3> periodic{true, true, true};

  double length(int d) const { return upper[d] - lower[d]; }
  double spacing(int d) const { return length(d) / static_cast<double>(cells[d]); }
};

/// How the grid is split over ranks. `slabs_in_z` gives each rank a slab of whole x-y planes with the
/// z ownership of `z_ownership` (the FFT solver needs FFTW-MPI's slab decomposition).
struct Decomposition {
  bool slabs_in_z = false;
  std::vector<PetscInt> z_ownership; // cells per rank along z when slabs_in_z; empty = PETSc's choice
};

class StaggeredGrid {
 public:
  /// `stencil_width` ghost cells on each side (2 for the limited upwind convection).
  StaggeredGrid(MPI_Comm comm, const BoxGeometry& box, const Decomposition& decomposition = {},
                PetscInt stencil_width = 2);
  StaggeredGrid(const StaggeredGrid&) = delete;
  StaggeredGrid& operator=(const StaggeredGrid&) = delete;

  DM dm() const { return dm_.get(); }
  MPI_Comm comm() const { return comm_; }
  const BoxGeometry& box() const { return box_; }
  double h(int d) const { return h_[d]; }
  double cell_volume() const { return h_[0] * h_[1] * h_[2]; }
  PetscInt cells(int d) const { return box_.cells[d]; }
  bool periodic(int d) const { return box_.periodic[d]; }

  /// First owned element index and owned element count per direction.
  PetscInt begin(int d) const { return begin_[d]; }
  PetscInt count(int d) const { return count_[d]; }
  /// True on the rank that owns the box's upper side in direction d.
  bool owns_upper(int d) const { return owns_upper_[d]; }
  /// True on the rank that owns the box's lower side in direction d.
  bool owns_lower(int d) const { return begin_[d] == 0; }
  /// The owned index range [lo, hi) of faces normal to `component` in direction d.
  PetscInt face_end(int component, int d) const
  {
    return begin_[d] + count_[d] + ((component == d && !box_.periodic[d] && owns_upper_[d]) ? 1 : 0);
  }
  /// The ghosted element range [ghost_begin, ghost_end) of a local array in direction d.
  PetscInt ghost_begin(int d) const { return ghost_begin_[d]; }
  PetscInt ghost_end(int d) const { return ghost_begin_[d] + ghost_count_[d]; }

  PetscInt face_slot(int d) const { return face_slot_[d]; }
  PetscInt pressure_slot() const { return pressure_slot_; }

  /// Position of the face of `component` with indices (i,j,k), and of the cell centre (i,j,k).
  Real3 face_position(int component, PetscInt i, PetscInt j, PetscInt k) const
  {
    Real3 x = cell_center(i, j, k);
    x[component] -= 0.5 * h_[component];
    return x;
  }
  Real3 cell_center(PetscInt i, PetscInt j, PetscInt k) const
  {
    return {box_.lower[0] + (static_cast<double>(i) + 0.5) * h_[0],
            box_.lower[1] + (static_cast<double>(j) + 0.5) * h_[1],
            box_.lower[2] + (static_cast<double>(k) + 0.5) * h_[2]};
  }
  /// True when the face of `component` with index `index` along `component` lies on the box boundary.
  bool is_boundary_face(int component, PetscInt index) const
  {
    return !box_.periodic[component] && (index == 0 || index == box_.cells[component]);
  }

  /// A new global vector (faces + cells), zeroed.
  petsc::OwnedVec create_global() const;
  /// A new local (ghosted) vector, zeroed.
  petsc::OwnedVec create_local() const;
  /// Ghost exchange: fills `local` (interior and ghosts from neighbouring ranks / periodic images).
  void global_to_local(Vec global, Vec local) const;

 private:
  MPI_Comm comm_;
  BoxGeometry box_;
  petsc::OwnedDM dm_;
  Real3 h_{};
  Index3 begin_{}, count_{}, ghost_begin_{}, ghost_count_{};
  std::array<bool, 3> owns_upper_{};
  std::array<PetscInt, 3> face_slot_{};
  PetscInt pressure_slot_ = 0;
};

/// Read-write access to a local (ghosted) DMStag vector as a(i, j, k, slot) with global indices (RAII).
/// A local vector stores every ghosted element with all its dofs, element-major, x fastest.
class StagArray {
 public:
  StagArray(const StaggeredGrid& grid, Vec local, bool read_only = false);
  ~StagArray();
  StagArray(const StagArray&) = delete;
  StagArray& operator=(const StagArray&) = delete;
  PetscScalar& operator()(PetscInt i, PetscInt j, PetscInt k, PetscInt slot) const
  {
    return data_[((k - g_[2]) * n_[1] + (j - g_[1])) * stride_y_ + (i - g_[0]) * dof_ + slot];
  }
  /// Distance in entries between neighbours along x, y, z.
  PetscInt stride(int d) const { return d == 0 ? dof_ : d == 1 ? stride_y_ : stride_y_ * n_[1]; }

 private:
  Vec v_;
  bool read_only_;
  PetscScalar* data_ = nullptr;
  Index3 g_{}, n_{};
  PetscInt dof_ = 4, stride_y_ = 0;
};

} // namespace ibvalve::fluid
