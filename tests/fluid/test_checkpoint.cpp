// Runs on 2 ranks: NavierStokes::save/restore (the checkpoints of `ibvalve run --restart`).
//  - A run saved after 3 steps and restored into a new solver continues exactly like the run that
//    was never interrupted: the fields after 6 steps are the same bits, on 2 ranks and on 1.
//  - The file does not depend on the decomposition: 2 ranks write, 1 rank reads, and saving again
//    gives back every dataset bit for bit; continuing there agrees with the 2-rank run to round-off.
// Both solvers: the FFT solver on a periodic box (z slabs) and the Krylov solver on a box with a
// velocity inlet, a traction outlet and walls (the extra face layers of non-periodic directions).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include "fluid/navier_stokes.hpp"
#include "fluid/queries.hpp"
#include "io/hdf5.hpp"
#include "tests/fluid/exact_solutions.hpp"
#include "tests/fluid/whole_flows.hpp"

namespace ibvalve::fluid {
namespace {

/// A file name every rank of the world agrees on (rank 0's process id), with a tag.
std::filesystem::path shared_path(const std::string& tag)
{
  int pid = static_cast<int>(::getpid());
  MPI_Bcast(&pid, 1, MPI_INT, 0, PETSC_COMM_WORLD);
  return std::filesystem::temp_directory_path() /
         (fmt::format("ibvalve_fluid_checkpoint_{}_{}.h5", tag, pid));
}

using testing::gather_fields;
using testing::world_rank;

using FlowSetup = std::function<std::unique_ptr<NavierStokes>(MPI_Comm)>;

std::unique_ptr<NavierStokes> abc_flow(MPI_Comm comm)
{
  return testing::abc_flow(comm, 8);
}

/// The jet with a traction outflow; its body force is kept between steps, so the checkpoint must carry it.
std::unique_ptr<NavierStokes> jet_in_a_box(MPI_Comm comm)
{
  return testing::jet_in_a_box(comm, {12, 6, 6}, false);
}

/// Uninterrupted for 2n steps vs. n steps, save, restore into a new solver, n more: the same bits.
void expect_restart_exact(const FlowSetup& setup, MPI_Comm comm, const std::filesystem::path& file, int n,
                          double dt)
{
  auto whole = setup(comm);
  for (int s = 0; s < 2 * n; ++s) whole->step(dt);
  auto first = setup(comm);
  for (int s = 0; s < n; ++s) first->step(dt);
  {
    io::Hdf5File h5(comm, file, io::Hdf5File::Mode::create);
    first->save(h5, "fluid");
  }
  auto second = setup(comm);
  {
    io::Hdf5File h5(comm, file, io::Hdf5File::Mode::read);
    second->restore(h5, "fluid");
  }
  EXPECT_EQ(second->steps_taken(), n);
  EXPECT_EQ(second->time(), first->time());
  for (int s = 0; s < n; ++s) second->step(dt);
  EXPECT_EQ(second->time(), whole->time());
  const std::vector<double> a = gather_fields(*whole), b = gather_fields(*second);
  std::size_t differing = 0;
  for (std::size_t q = 0; q < a.size(); ++q) differing += a[q] != b[q] ? 1 : 0;
  EXPECT_EQ(differing, 0u) << "values of the restarted run that differ from the uninterrupted run's";
}

/// Written on 2 ranks, read on 1: saving again gives the same datasets; continuing agrees to round-off.
void expect_readable_on_one_rank(const FlowSetup& setup, const std::filesystem::path& file, int n, double dt,
                                 const char* name)
{
  auto two = setup(PETSC_COMM_WORLD);
  for (int s = 0; s < n; ++s) two->step(dt);
  {
    io::Hdf5File h5(PETSC_COMM_WORLD, file, io::Hdf5File::Mode::create);
    two->save(h5, "fluid");
  }
  const std::vector<double> restored_two = gather_fields(*two);
  for (int s = 0; s < n; ++s) two->step(dt);
  const std::vector<double> continued_two = gather_fields(*two);
  MPI_Barrier(PETSC_COMM_WORLD);
  // Every rank does the 1-rank part on its own (as in test_ranks_and_conservation.cpp).
  MPI_Comm alone;
  MPI_Comm_split(PETSC_COMM_WORLD, world_rank(), 0, &alone);
  auto one = setup(alone);
  {
    io::Hdf5File h5(alone, file, io::Hdf5File::Mode::read);
    one->restore(h5, "fluid");
  }
  const std::filesystem::path again = fmt::format("{}.rank{}.h5", file.string(), world_rank());
  {
    io::Hdf5File h5(alone, again, io::Hdf5File::Mode::create);
    one->save(h5, "fluid");
  }
  {
    io::Hdf5File original(alone, file, io::Hdf5File::Mode::read),
        copy(alone, again, io::Hdf5File::Mode::read);
    for (const char* dataset : {"fluid/state", "fluid/convection", "fluid/body_force", "fluid/clock"})
      EXPECT_EQ(original.read(dataset), copy.read(dataset)) << dataset << " read on 1 rank and saved again";
    EXPECT_EQ(original.read_integers("fluid/counters"), copy.read_integers("fluid/counters"));
  }
  std::filesystem::remove(again);
  EXPECT_EQ(gather_fields(*one), restored_two) << "the restored fields on 1 rank";
  for (int s = 0; s < n; ++s) one->step(dt);
  const std::vector<double> continued_one = gather_fields(*one);
  MPI_Comm_free(&alone);
  double largest = 0.0, difference = 0.0;
  for (std::size_t q = 0; q < continued_one.size(); ++q) {
    largest = std::max(largest, std::abs(continued_two[q]));
    difference = std::max(difference, std::abs(continued_one[q] - continued_two[q]));
  }
  if (world_rank() == 0)
    std::printf("%s: written on 2 ranks, continued on 1: max difference %.2e (fields up to %.2e)\n", name,
                difference, largest);
  EXPECT_LT(difference, 1e-10 * largest);
}

void expect_checkpoints_work(const FlowSetup& setup, int n, double dt, const char* name,
                             const std::string& tag)
{
  int size = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  ASSERT_EQ(size, 2) << "this test runs on 2 ranks";
  const std::filesystem::path file = shared_path(tag);
  expect_restart_exact(setup, PETSC_COMM_WORLD, file, n, dt);
  MPI_Comm alone;
  MPI_Comm_split(PETSC_COMM_WORLD, world_rank(), 0, &alone);
  expect_restart_exact(setup, alone, fmt::format("{}.rank{}.h5", file.string(), world_rank()), n, dt);
  MPI_Comm_free(&alone);
  MPI_Barrier(PETSC_COMM_WORLD);
  expect_readable_on_one_rank(setup, file, n, dt, name);
  MPI_Barrier(PETSC_COMM_WORLD);
  if (world_rank() == 0) std::filesystem::remove(file);
  std::filesystem::remove(fmt::format("{}.rank{}.h5", file.string(), world_rank()));
}

TEST(Checkpoint, PeriodicFftRunRestartsExactly)
{
  expect_checkpoints_work(abc_flow, 3, 0.0625 / 8, "ABC fft 8^3", "fft");
}

TEST(Checkpoint, KrylovRunWithInletOutletAndWallsRestartsExactly)
{
  expect_checkpoints_work(jet_in_a_box, 3, 0.02, "jet in a box, krylov", "krylov");
}

} // namespace
} // namespace ibvalve::fluid
