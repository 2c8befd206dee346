// Owned PETSc objects (io/petsc_handle.hpp): an Owned destroys its object on scope exit, also when an
// exception is thrown between create and use; a move leaves the source null; out() destroys the
// object held before; a shared owner drops only its own reference. Each test keeps an extra reference to the
// object it hands over and reads the reference count back, so a wrapper that did not destroy leaves a count
// of 2 and fails.
#include <stdexcept>
#include <utility>

#include <gtest/gtest.h>

#include "io/petsc_handle.hpp"

namespace ibvalve::petsc {
namespace {

/// A small parallel Vec the caller must destroy.
Vec new_vec()
{
  Vec v = nullptr;
  PETSC_CHECK(VecCreateMPI(PETSC_COMM_WORLD, 3, PETSC_DETERMINE, &v));
  return v;
}

/// References held on `v` (PetscObjectGetReference).
PetscInt references(Vec v)
{
  PetscInt count = 0;
  PETSC_CHECK(PetscObjectGetReference(reinterpret_cast<PetscObject>(v), &count));
  return count;
}

/// Takes one more reference on `v`, so it outlives the Owned under test and can be counted.
Vec watch(Vec v)
{
  PETSC_CHECK(PetscObjectReference(reinterpret_cast<PetscObject>(v)));
  return v;
}

TEST(PetscHandle, DestroysOnScopeExit)
{
  Vec kept = nullptr;
  {
    OwnedVec v(new_vec());
    kept = watch(v);
    EXPECT_EQ(references(kept), 2);
  }
  EXPECT_EQ(references(kept), 1);
  PETSC_CHECK(VecDestroy(&kept));
}

TEST(PetscHandle, DestroysWhenAnExceptionIsThrownBetweenCreateAndUse)
{
  Vec kept = nullptr;
  // PETSc's default handler would print a traceback for the failure this test provokes.
  PETSC_CHECK(PetscPushErrorHandler(PetscReturnErrorHandler, nullptr));
  EXPECT_THROW(
      {
        OwnedVec v;
        PETSC_CHECK(VecCreateMPI(PETSC_COMM_WORLD, 3, PETSC_DETERMINE, v.out()));
        kept = watch(v);
        // A failing PETSc call between create and use: PETSC_CHECK throws PetscFailure.
        PETSC_CHECK(VecSetSizes(v, 5, PETSC_DETERMINE));
        PETSC_CHECK(VecSet(v, 1.0));
      },
      PetscFailure);
  PETSC_CHECK(PetscPopErrorHandler());
  ASSERT_NE(kept, nullptr);
  EXPECT_EQ(references(kept), 1);
  PETSC_CHECK(VecDestroy(&kept));
}

TEST(PetscHandle, MovesLeaveTheSourceNullAndTransferOwnership)
{
  OwnedVec a(new_vec());
  Vec kept = watch(a);
  OwnedVec b(std::move(a));
  EXPECT_FALSE(a);
  EXPECT_EQ(a.get(), nullptr);
  EXPECT_EQ(b.get(), kept);

  OwnedVec c;
  c = std::move(b);
  EXPECT_FALSE(b);
  EXPECT_EQ(c.get(), kept);
  EXPECT_EQ(references(kept), 2);

  // Move assignment over a held object destroys it.
  OwnedVec d(new_vec());
  Vec replaced = watch(d);
  d = std::move(c);
  EXPECT_EQ(references(replaced), 1);
  EXPECT_EQ(d.get(), kept);
  d.reset();
  EXPECT_FALSE(d);
  EXPECT_EQ(references(kept), 1);
  PETSC_CHECK(VecDestroy(&kept));
  PETSC_CHECK(VecDestroy(&replaced));
}

TEST(PetscHandle, OutDestroysThePreviousObject)
{
  OwnedVec v(new_vec());
  Vec first = watch(v);
  PETSC_CHECK(VecDuplicate(first, v.out()));
  EXPECT_EQ(references(first), 1);
  EXPECT_NE(v.get(), first);
  EXPECT_EQ(references(v), 1);
  PETSC_CHECK(VecDestroy(&first));
}

TEST(PetscHandle, ReleaseGivesOwnershipAway)
{
  OwnedVec v(new_vec());
  Vec raw_vec = v.release();
  EXPECT_FALSE(v);
  EXPECT_EQ(references(raw_vec), 1);
  PETSC_CHECK(VecDestroy(&raw_vec));
}

TEST(PetscHandle, SharedOwnersEachDropOneReference)
{
  OwnedVec first(new_vec());
  Vec kept = watch(first);
  {
    const OwnedVec second = OwnedVec::shared(first);
    EXPECT_EQ(second.get(), kept);
    EXPECT_EQ(references(kept), 3);
  }
  EXPECT_EQ(references(kept), 2);
  first.reset();
  EXPECT_EQ(references(kept), 1);
  PETSC_CHECK(VecDestroy(&kept));
}

TEST(PetscHandle, DuplicatesAreOwnedOneByOne)
{
  OwnedVec model(new_vec());
  Vec kept = nullptr;
  {
    std::vector<OwnedVec> copies = duplicate_vecs(model, 3);
    ASSERT_EQ(copies.size(), 3u);
    const std::vector<Vec> handles = raw(copies);
    EXPECT_EQ(handles[1], copies[1].get());
    kept = watch(copies[2]);
  }
  EXPECT_EQ(references(kept), 1);
  PETSC_CHECK(VecDestroy(&kept));
}

} // namespace
} // namespace ibvalve::petsc
