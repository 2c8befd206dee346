// GoogleTest entry point for every ibvalve test program.
//
// Every run of ibvalve is an MPI run, and so is every test: MPI and PETSc are initialised once here.
// Each rank runs every test; only rank 0 prints GoogleTest's report, and the program fails when any
// rank saw a failure, so a 2-rank test cannot pass on one rank and fail silently on the other.
#include <gtest/gtest.h>
#include <mpi.h>
#include <petscsys.h>

int main(int argc, char** argv)
{
  ::testing::InitGoogleTest(&argc, argv);
  // PETSc options may follow on the command line (for example -ksp_monitor); GoogleTest has
  // already removed its own flags.
  if (PetscInitialize(&argc, &argv, nullptr, nullptr) != 0) return 1;
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank != 0) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  const int local_result = RUN_ALL_TESTS();
  int global_result = 0;
  MPI_Allreduce(&local_result, &global_result, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD);
  if (PetscFinalize() != 0) return 1;
  return global_result;
}
