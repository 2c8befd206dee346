#include "ib/interaction.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include <mpi.h>

#include "io/errors.hpp"
#include "io/petsc_check.hpp"

namespace ibvalve::ib {

namespace {

// Read-write access to a local vector of the interaction's own DMStag as a[k][j][i][slot].
class LocalArray {
 public:
  LocalArray(DM dm, Vec v) : dm_(dm), v_(v) { PETSC_CHECK(DMStagVecGetArray(dm_, v_, &a_)); }
  ~LocalArray() { DMStagVecRestoreArray(dm_, v_, &a_); }
  LocalArray(const LocalArray&) = delete;
  LocalArray& operator=(const LocalArray&) = delete;
  PetscScalar& operator()(PetscInt i, PetscInt j, PetscInt k, PetscInt slot) const
  {
    return a_[k][j][i][slot];
  }

 private:
  DM dm_;
  Vec v_;
  PetscScalar**** a_ = nullptr;
};

} // namespace

GridInteraction::GridInteraction(const fluid::StaggeredGrid& grid, KernelKind kernel)
    : grid_(grid), kernel_(kernel)
{
  PetscInt ranks[3];
  PETSC_CHECK(DMStagGetNumRanks(grid.dm(), &ranks[0], &ranks[1], &ranks[2]));
  const PetscInt *lx = nullptr, *ly = nullptr, *lz = nullptr;
  PETSC_CHECK(DMStagGetOwnershipRanges(grid.dm(), &lx, &ly, &lz));
  auto boundary = [&](int d) { return grid.periodic(d) ? DM_BOUNDARY_PERIODIC : DM_BOUNDARY_GHOSTED; };
  // One dof per face, nothing elsewhere; the same ownership as the fluid grid, so owned faces match.
  PETSC_CHECK(DMStagCreate3d(grid.comm(), boundary(0), boundary(1), boundary(2), grid.cells(0), grid.cells(1),
                             grid.cells(2), ranks[0], ranks[1], ranks[2], 0, 0, 1, 0, DMSTAG_STENCIL_BOX,
                             kernel_.ghost_width(), lx, ly, lz, &dm_));
  PETSC_CHECK(DMSetUp(dm_));
  const DMStagStencilLocation faces[3] = {DMSTAG_LEFT, DMSTAG_DOWN, DMSTAG_BACK};
  for (int d = 0; d < 3; ++d) PETSC_CHECK(DMStagGetLocationSlot(dm_, faces[d], 0, &slot_[d]));
  PETSC_CHECK(DMStagGetEntriesPerElement(dm_, &stride_));
  PETSC_CHECK(DMCreateGlobalVector(dm_, &global_));
  PETSC_CHECK(DMCreateLocalVector(dm_, &local_));
  for (int d = 0; d < 3; ++d)
    if (grid.count(d) < kernel_.ghost_width())
      throw std::invalid_argument("ib: each rank needs at least " + std::to_string(kernel_.ghost_width()) +
                                  " cells per direction for the " + kernel_.name() + " kernel");
}

GridInteraction::~GridInteraction()
{
  if (global_) VecDestroy(&global_);
  if (local_) VecDestroy(&local_);
  if (dm_) DMDestroy(&dm_);
}

Vec3 GridInteraction::wrap(const Vec3& x) const
{
  const fluid::BoxGeometry& box = grid_.box();
  Vec3 y = x;
  for (int d = 0; d < 3; ++d) {
    if (!std::isfinite(x[d])) {
      std::ostringstream msg;
      msg << "ib: a structure point has a non-finite position (" << x.transpose() << "): the run diverged";
      throw RunError(msg.str());
    }
    if (grid_.periodic(d)) {
      const double L = box.length(d);
      y[d] = box.lower[d] + (x[d] - box.lower[d]) - L * std::floor((x[d] - box.lower[d]) / L);
    } else if (x[d] < box.lower[d] || x[d] > box.upper[d]) {
      std::ostringstream msg;
      msg << "ib: structure point (" << x.transpose() << ") left the grid: direction "
          << "xyz"[d] << " spans [" << box.lower[d] << ", " << box.upper[d] << "]";
      throw RunError(msg.str());
    }
  }
  return y;
}

bool GridInteraction::owns(const Vec3& x) const
{
  const Vec3 y = wrap(x);
  for (int d = 0; d < 3; ++d) {
    auto cell = static_cast<PetscInt>(std::floor((y[d] - grid_.box().lower[d]) / grid_.h(d)));
    cell = std::clamp<PetscInt>(cell, 0, grid_.cells(d) - 1); // x == upper belongs to the last cell
    if (cell < grid_.begin(d) || cell >= grid_.begin(d) + grid_.count(d)) return false;
  }
  return true;
}

GridInteraction::Stencil GridInteraction::stencil(const Vec3& y) const
{
  Stencil s;
  for (int e = 0; e < 3; ++e) {
    const double t = (y[e] - grid_.box().lower[e]) / grid_.h(e);
    s.first_face[e] = kernel_.weights(t, s.weights_face[e]);           // faces normal to e sit at t = i
    s.first_center[e] = kernel_.weights(t - 0.5, s.weights_center[e]); // cell centres at t = i + 1/2
  }
  return s;
}

std::pair<int, int> GridInteraction::valid_range(int component, int e, int first) const
{
  const int support = kernel_.support();
  if (grid_.periodic(e)) return {0, support};
  const PetscInt last = component == e ? grid_.cells(e) : grid_.cells(e) - 1;
  const int lo = static_cast<int>(std::max<PetscInt>(0, -first));
  const int hi = static_cast<int>(std::min<PetscInt>(support, last - first + 1));
  return {lo, std::max(lo, hi)};
}

void GridInteraction::interpolate(Vec velocity, std::span<const Vec3> points, std::span<Vec3> values)
{
  // Copy the owned face values into this interaction's ghosted layout and exchange ghosts.
  {
    fluid::StagArray u(grid_, velocity, true);
    LocalArray a(dm_, local_);
    for (int d = 0; d < 3; ++d)
      for (PetscInt k = grid_.begin(2); k < grid_.face_end(d, 2); ++k)
        for (PetscInt j = grid_.begin(1); j < grid_.face_end(d, 1); ++j)
          for (PetscInt i = grid_.begin(0); i < grid_.face_end(d, 0); ++i)
            a(i, j, k, slot_[d]) = u(i, j, k, grid_.face_slot(d));
  }
  PETSC_CHECK(DMLocalToGlobal(dm_, local_, INSERT_VALUES, global_));
  PETSC_CHECK(DMGlobalToLocal(dm_, global_, INSERT_VALUES, local_));

  LocalArray a(dm_, local_);
  for (std::size_t p = 0; p < points.size(); ++p) {
    values[p].setZero();
    if (!owns(points[p])) continue;
    const Stencil s = stencil(wrap(points[p]));
    for (int d = 0; d < 3; ++d) {
      const auto& w0 = d == 0 ? s.weights_face[0] : s.weights_center[0];
      const auto& w1 = d == 1 ? s.weights_face[1] : s.weights_center[1];
      const auto& w2 = d == 2 ? s.weights_face[2] : s.weights_center[2];
      const int f0 = d == 0 ? s.first_face[0] : s.first_center[0];
      const int f1 = d == 1 ? s.first_face[1] : s.first_center[1];
      const int f2 = d == 2 ? s.first_face[2] : s.first_center[2];
      const auto [a0, b0] = valid_range(d, 0, f0);
      const auto [a1, b1] = valid_range(d, 1, f1);
      const auto [a2, b2] = valid_range(d, 2, f2);
      if (a0 >= b0) continue; // the whole stencil lies outside a walled box (the point is on a wall)
      double sum = 0.0;
      for (int c = a2; c < b2; ++c)
        for (int b = a1; b < b1; ++b) {
          double row = 0.0;
          // Along x the entries of one (j, k) row are contiguous, `stride_` apart.
          const PetscScalar* entry = &a(f0 + a0, f1 + b, f2 + c, slot_[d]);
          for (int m = a0; m < b0; ++m, entry += stride_) row += w0[m] * *entry;
          sum += w2[c] * w1[b] * row;
        }
      values[p][d] = sum;
    }
  }
}

void GridInteraction::spread(std::span<const Vec3> points, std::span<const Vec3> forces, Vec force, bool add)
{
  PETSC_CHECK(VecZeroEntries(local_));
  const double inverse_volume = 1.0 / grid_.cell_volume();
  {
    LocalArray a(dm_, local_);
    for (std::size_t p = 0; p < points.size(); ++p) {
      if (!owns(points[p])) continue;
      const Stencil s = stencil(wrap(points[p]));
      for (int d = 0; d < 3; ++d) {
        const double F = forces[p][d] * inverse_volume;
        if (F == 0.0) continue;
        const auto& w0 = d == 0 ? s.weights_face[0] : s.weights_center[0];
        const auto& w1 = d == 1 ? s.weights_face[1] : s.weights_center[1];
        const auto& w2 = d == 2 ? s.weights_face[2] : s.weights_center[2];
        const int f0 = d == 0 ? s.first_face[0] : s.first_center[0];
        const int f1 = d == 1 ? s.first_face[1] : s.first_center[1];
        const int f2 = d == 2 ? s.first_face[2] : s.first_center[2];
        const auto [a0, b0] = valid_range(d, 0, f0);
        const auto [a1, b1] = valid_range(d, 1, f1);
        const auto [a2, b2] = valid_range(d, 2, f2);
        if (a0 >= b0) continue;
        for (int c = a2; c < b2; ++c)
          for (int b = a1; b < b1; ++b) {
            const double wbc = F * w2[c] * w1[b];
            PetscScalar* entry = &a(f0 + a0, f1 + b, f2 + c, slot_[d]);
            for (int m = a0; m < b0; ++m, entry += stride_) *entry += wbc * w0[m];
          }
      }
    }
  }
  // Ghost contributions (other ranks' faces, periodic images) go to their owners.
  PETSC_CHECK(VecZeroEntries(global_));
  PETSC_CHECK(DMLocalToGlobal(dm_, local_, ADD_VALUES, global_));
  PETSC_CHECK(DMGlobalToLocal(dm_, global_, INSERT_VALUES, local_));
  LocalArray a(dm_, local_);
  fluid::StagArray f(grid_, force);
  for (int d = 0; d < 3; ++d)
    for (PetscInt k = grid_.begin(2); k < grid_.face_end(d, 2); ++k)
      for (PetscInt j = grid_.begin(1); j < grid_.face_end(d, 1); ++j)
        for (PetscInt i = grid_.begin(0); i < grid_.face_end(d, 0); ++i) {
          PetscScalar& target = f(i, j, k, grid_.face_slot(d));
          target = (add ? target : 0.0) + a(i, j, k, slot_[d]);
        }
}

double GridInteraction::inner_product(Vec va, Vec vb) const
{
  fluid::StagArray a(grid_, va, true), b(grid_, vb, true);
  double sum = 0.0;
  for (int d = 0; d < 3; ++d)
    for (PetscInt k = grid_.begin(2); k < grid_.face_end(d, 2); ++k)
      for (PetscInt j = grid_.begin(1); j < grid_.face_end(d, 1); ++j)
        for (PetscInt i = grid_.begin(0); i < grid_.face_end(d, 0); ++i)
          sum += a(i, j, k, grid_.face_slot(d)) * b(i, j, k, grid_.face_slot(d));
  double total = 0.0;
  MPI_Allreduce(&sum, &total, 1, MPI_DOUBLE, MPI_SUM, grid_.comm());
  return total * grid_.cell_volume();
}

} // namespace ibvalve::ib
