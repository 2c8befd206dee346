#pragma once
// Owned PETSc objects. A PETSc handle (Vec, Mat, KSP, ...) is a pointer its creator must destroy;
// held raw beside exceptions (PETSC_CHECK throws) it leaks on every error path. petsc::Owned holds one
// handle and destroys it when it goes out of scope, so no code outside this header calls *Destroy.
//
// One naming scheme: petsc::OwnedVec, petsc::OwnedMat, ... (never petsc::Vec, which would shadow
// PETSc's own type names inside namespace ibvalve).
#include <cstddef>
#include <span>
#include <utility>
#include <vector>

#include <petscdm.h>
#include <petscis.h>
#include <petscksp.h>
#include <petscmat.h>
#include <petscsnes.h>
#include <petscvec.h>

#include "io/petsc_check.hpp"

namespace ibvalve::petsc {

/// Owns one PETSc object of type Handle, destroyed by `destroy` (VecDestroy, MatDestroy, ...).
/// Move-only: exactly one owner at a time; a moved-from Owned is null.
template <class Handle, PetscErrorCode (*destroy)(Handle*)>
class Owned {
 public:
  Owned() = default;
  /// Adopts `handle` (it must not be destroyed elsewhere).
  explicit Owned(Handle handle) noexcept : handle_(handle) {}

  /// A further owner of `handle`, which stays owned elsewhere too: takes a PETSc reference
  /// (PetscObjectReference), so each owner's destroy drops one and the last frees the object.
  [[nodiscard]] static Owned shared(Handle handle)
  {
    if (handle) PETSC_CHECK(PetscObjectReference(reinterpret_cast<PetscObject>(handle)));
    return Owned(handle);
  }

  Owned(const Owned&) = delete;
  Owned& operator=(const Owned&) = delete;
  Owned(Owned&& other) noexcept : handle_(std::exchange(other.handle_, nullptr)) {}
  Owned& operator=(Owned&& other) noexcept
  {
    if (this != &other) {
      destroy_quietly();
      handle_ = std::exchange(other.handle_, nullptr);
    }
    return *this;
  }

  // A destructor cannot throw (it may run during unwinding from another PETSc error), so the code a
  // destroy returns is dropped here; code that must see it destroys early with reset().
  ~Owned() { destroy_quietly(); }

  [[nodiscard]] Handle get() const noexcept { return handle_; }
  /// Lets PETSc calls take an Owned where they take the handle: VecAXPY(y, a, x).
  operator Handle() const& noexcept { return handle_; }
  /// Not from a temporary: `Vec v = grid.create_global();` would keep a handle the temporary destroys.
  operator Handle() && = delete;
  explicit operator bool() const noexcept { return handle_ != nullptr; }

  /// Destroys any held object and returns the slot for a PETSc create function to fill:
  /// PETSC_CHECK(VecDuplicate(x, y.out())).
  [[nodiscard]] Handle* out()
  {
    reset();
    return &handle_;
  }

  /// Destroys the held object now (checked: a failure throws PetscFailure); null afterwards.
  void reset()
  {
    if (handle_) PETSC_CHECK(destroy(&handle_));
    handle_ = nullptr;
  }

  /// Gives the handle up without destroying it; the caller owns it afterwards.
  [[nodiscard]] Handle release() noexcept { return std::exchange(handle_, nullptr); }

 private:
  void destroy_quietly() noexcept
  {
    if (handle_) static_cast<void>(destroy(&handle_));
    handle_ = nullptr;
  }

  Handle handle_ = nullptr;
};

using OwnedVec = Owned<Vec, VecDestroy>;
using OwnedMat = Owned<Mat, MatDestroy>;
using OwnedKSP = Owned<KSP, KSPDestroy>;
using OwnedIS = Owned<IS, ISDestroy>;
using OwnedVecScatter = Owned<VecScatter, VecScatterDestroy>;
using OwnedDM = Owned<DM, DMDestroy>;
using OwnedSNES = Owned<SNES, SNESDestroy>;
using OwnedMatNullSpace = Owned<MatNullSpace, MatNullSpaceDestroy>;
using OwnedPetscRandom = Owned<PetscRandom, PetscRandomDestroy>;

/// `count` duplicates of `model` (VecDuplicateVecs), each owned on its own so they can be handed
/// around or dropped one at a time like any OwnedVec.
[[nodiscard]] inline std::vector<OwnedVec> duplicate_vecs(Vec model, std::size_t count)
{
  std::vector<OwnedVec> vecs;
  vecs.reserve(count);
  for (std::size_t i = 0; i < count; ++i) PETSC_CHECK(VecDuplicate(model, vecs.emplace_back().out()));
  return vecs;
}

/// The raw handles of `vecs`, for PETSc calls that take a Vec array (VecMAXPY, VecMDot, ...); the
/// array borrows: `vecs` still owns every Vec.
[[nodiscard]] inline std::vector<Vec> raw(const std::vector<OwnedVec>& vecs)
{
  std::vector<Vec> handles;
  handles.reserve(vecs.size());
  for (const OwnedVec& v : vecs) handles.push_back(v.get());
  return handles;
}

/// A Vec's local values, read and written in place while the object lives (VecGetArray), and given
/// back when it goes (also when the code using them throws).
class VecArray {
 public:
  explicit VecArray(Vec v) : v_(v) { PETSC_CHECK(VecGetArray(v_, &a_)); }
  ~VecArray() { VecRestoreArray(v_, &a_); }
  VecArray(const VecArray&) = delete;
  VecArray& operator=(const VecArray&) = delete;
  PetscScalar* data() const { return a_; }

 private:
  Vec v_;
  PetscScalar* a_ = nullptr;
};

/// Scatters `from` into `to` (forward, inserting) and calls use(values) with `to`'s local values, read in
/// place; the array is given back also when `use` throws. Collective over the scatter's ranks.
template <class Use>
void with_scattered(VecScatter scatter, Vec from, Vec to, Use&& use)
{
  PETSC_CHECK(VecScatterBegin(scatter, from, to, INSERT_VALUES, SCATTER_FORWARD));
  PETSC_CHECK(VecScatterEnd(scatter, from, to, INSERT_VALUES, SCATTER_FORWARD));
  PetscInt n = 0;
  PETSC_CHECK(VecGetLocalSize(to, &n));
  const PetscScalar* a = nullptr;
  PETSC_CHECK(VecGetArrayRead(to, &a));
  try {
    use(std::span<const double>(a, static_cast<std::size_t>(n)));
  } catch (...) {
    VecRestoreArrayRead(to, &a);
    throw;
  }
  PETSC_CHECK(VecRestoreArrayRead(to, &a));
}

} // namespace ibvalve::petsc
