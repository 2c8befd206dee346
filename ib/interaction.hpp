#pragma once
// Interpolation of the staggered velocity to arbitrary points and spreading of point forces to the
// face grids, on the distributed StaggeredGrid of fluid/ (Peskin 2002, eqs. 4.1 and 4.2 discretized):
//
//   (J u)_d(X)   = sum over faces x of component d of  u_d(x) delta_h(x - X) h^3
//   (S F)_d(x)   = sum over points X of  F_d(X) delta_h(x - X)
//
// so that sum_x (S F)(x) . u(x) h^3 = sum_X F(X) . (J u)(X) exactly (the two are adjoint).
//
// Parallel layout: every rank is given the same (replicated) list of points; each point is handled by
// the rank that owns the grid cell holding it. That rank reads velocities from its ghosted copy of the
// grid and spreads into it; the ghost parts of the spread force are then summed onto their owners
// (DMLocalToGlobal with ADD_VALUES). The interaction keeps one DMDA per velocity component, with the
// same ownership as that component's faces in the fluid grid and as many ghost layers as the kernel
// needs, so any kernel works on any fluid grid and each component's values lie contiguous along x (a
// stencil row is one run of memory, which the compiler vectorizes). Periodic directions wrap points
// into the box; in a non-periodic direction a point must stay inside the box (RunError otherwise), and
// kernel weights on grid points outside the box are dropped in both operators (which keeps them
// adjoint).
#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>
#include <petscdm.h>

#include "fluid/grid.hpp"
#include "ib/kernels.hpp"
#include "io/petsc_handle.hpp"

namespace ibvalve::ib {

using Vec3 = Eigen::Vector3d;

class GridInteraction {
 public:
  GridInteraction(const fluid::StaggeredGrid& grid, KernelKind kernel = default_kernel);
  GridInteraction(const GridInteraction&) = delete;
  GridInteraction& operator=(const GridInteraction&) = delete;

  const fluid::StaggeredGrid& grid() const { return grid_; }
  const DeltaKernel& kernel() const { return kernel_; }

  /// True when this rank handles the point (owns the cell that holds it). RunError when the point is
  /// outside a non-periodic side of the box (or not finite).
  bool owns(const Vec3& x) const;

  /// Interpolates the face velocities of `velocity` (a local vector of the fluid grid; only its owned
  /// face values are read) to the points. values[p] is set for the points this rank owns and zeroed
  /// for the others, so a sum over ranks gives every value once. Collective.
  void interpolate(Vec velocity, std::span<const Vec3> points, std::span<Vec3> values);

  /// Spreads the point forces onto the face grids and writes the result into the owned face slots of
  /// `force` (a local vector of the fluid grid): overwritten, or added to when `add`. Collective.
  void spread(std::span<const Vec3> points, std::span<const Vec3> forces, Vec force, bool add = false);

  /// The kernel weights of the points this rank handles, computed once while the points stand still
  /// and used by every interpolation and spreading from them (a coupled step interpolates twice and
  /// spreads once from two placements). `index[i]` is the position of prepared point i in the list
  /// given to prepare().
  class PreparedPoints {
   public:
    std::size_t size() const { return index.size(); }
    std::vector<std::size_t> index;

   private:
    friend class GridInteraction;
    // Per point, compact (a step holds one set for all its points): the support() weights per
    // direction on the face grid and on the cell centres, each set's first grid index, and a bit per
    // component whose whole stencil lies inside the box.
    std::vector<double> weights;           // 6 support() per point: face x, y, z, centre x, y, z (and
                                           // room for more: only the first size() points' are set)
    std::vector<std::array<int, 6>> first; // first_face[3], first_center[3]
    std::vector<std::uint8_t> inside;      // bit d: component d needs no clipping
  };

  /// Finds the points this rank handles and computes their stencils (RunError as owns()).
  void prepare(std::span<const Vec3> points, PreparedPoints& prepared) const;
  /// The same for the listed points only (ascending indices into `points`); the others are taken to
  /// be other ranks' (see may_hold).
  void prepare(std::span<const Vec3> points, std::span<const std::size_t> candidates,
               PreparedPoints& prepared) const;

  /// False only when no point inside the axis-aligned box [lower, upper] is one this rank handles:
  /// in some non-periodic direction the cells the box spans (counted as owns() counts them) miss this
  /// rank's. A box that reaches outside a non-periodic side, or is not finite, may hold anything (its
  /// points then raise owns()'s RunError on every rank). Points of an element interpolated with
  /// non-negative shape values lie in its nodes' bounding box.
  bool may_hold(const Vec3& lower, const Vec3& upper) const;
  /// interpolate() for prepared points: values[i] belongs to prepared point i. Collective.
  void interpolate(Vec velocity, const PreparedPoints& points, std::span<Vec3> values);
  /// spread() for prepared points: forces[i] belongs to prepared point i. Collective.
  void spread(const PreparedPoints& points, std::span<const Vec3> forces, Vec force, bool add = false);

  /// Sum over the owned faces of a . b h^3 (summed over ranks): the discrete L2 inner product of
  /// two face fields held in local vectors of the fluid grid.
  double inner_product(Vec a, Vec b) const;

 private:
  Vec3 wrap(const Vec3& x) const;
  /// True when the wrapped point y lies in a cell this rank owns.
  bool owns_wrapped(const Vec3& y) const;
  /// Position x along d in grid units from the box's lower side: face i sits at i, cell i spans [i, i+1).
  double grid_coordinate(int d, double x) const { return (x - grid_.box().lower[d]) / grid_.h(d); }
  /// The cell along d that holds grid coordinate s; s on the upper side belongs to the last cell.
  PetscInt cell_of(int d, double s) const
  {
    return std::clamp<PetscInt>(static_cast<PetscInt>(grid_floor(s)), 0, grid_.cells(d) - 1);
  }
  /// True when this rank owns cell `cell` along d: owns(), may_hold() and prepare() count alike.
  bool owns_cell(int d, PetscInt cell) const
  {
    return cell >= grid_.begin(d) && cell < grid_.begin(d) + grid_.count(d);
  }
  /// Copies the owned face values of `velocity` into the components' global vectors and exchanges
  /// their ghosts into the local ones.
  void gather_velocity(Vec velocity);
  /// Adds the local vectors' ghost parts to their owners and writes the owned faces into `force`.
  void scatter_force(Vec force, bool add);
  /// Empties `prepared` and makes room for the weights of `at_most` points.
  void start_preparing(std::size_t at_most, PreparedPoints& prepared) const;
  /// prepare()'s work for point p: adds it with its stencils when this rank handles it.
  void prepare_point(const Vec3& x, std::size_t p, PreparedPoints& prepared) const;
  /// Index range [lo, hi) of kernel offsets m that land on grid points inside the box.
  std::pair<int, int> valid_range(int component, int e, int first) const;
  /// Offset of face (i, j, k) of component d in that component's local array.
  PetscInt offset(int d, PetscInt i, PetscInt j, PetscInt k) const
  {
    const auto c = static_cast<std::size_t>(d);
    return (i - ghost_start_[c][0]) + (j - ghost_start_[c][1]) * row_stride_[c] +
           (k - ghost_start_[c][2]) * plane_stride_[c];
  }

  const fluid::StaggeredGrid& grid_;
  DeltaKernel kernel_;
  // Per velocity component d: a DMDA on the faces normal to d, its global and local vectors, and the
  // local array's ghost corner and strides (entries between neighbouring y rows and z planes).
  std::array<petsc::OwnedDM, 3> dm_;
  std::array<petsc::OwnedVec, 3> global_, local_; // after dm_: destroyed before it
  std::array<std::array<PetscInt, 3>, 3> ghost_start_{};
  std::array<PetscInt, 3> row_stride_{}, plane_stride_{};
};

} // namespace ibvalve::ib
