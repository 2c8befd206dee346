// Runs on 2 ranks: the same flows computed on 1 rank (a sub-communicator) and on 2 ranks agree to
// 1e-10 (fft solver on a periodic box, Krylov solver with traction and wall sides), and the volume
// flux into a closed box equals the flux out, through the sides and through interior planes.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>

#include "fluid/queries.hpp"
#include "tests/fluid/exact_solutions.hpp"
#include "tests/fluid/whole_flows.hpp"

namespace ibvalve::fluid {
namespace {

using testing::gather_fields;
using testing::world_rank;

using FlowSetup = std::function<std::unique_ptr<NavierStokes>(MPI_Comm)>;

/// Runs `steps` steps of the flow `setup` builds on `comm`, returns the gathered fields.
std::vector<double> run(const FlowSetup& setup, MPI_Comm comm, int steps, double dt)
{
  auto fluid = setup(comm);
  for (int s = 0; s < steps; ++s) fluid->step(dt);
  return gather_fields(*fluid);
}

void expect_same_on_one_and_two_ranks(const FlowSetup& setup, int steps, double dt, const char* name)
{
  int size = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  ASSERT_EQ(size, 2) << "this test runs on 2 ranks";
  const std::vector<double> two = run(setup, PETSC_COMM_WORLD, steps, dt);
  MPI_Comm alone;
  MPI_Comm_split(PETSC_COMM_WORLD, world_rank(), 0, &alone);
  // Every rank computes the 1-rank solution on its own (a rank idling in a collective of the world
  // communicator while another creates objects on a sub-communicator can stall Open MPI).
  const std::vector<double> one = run(setup, alone, steps, dt);
  MPI_Comm_free(&alone);
  if (world_rank() != 0) return;
  double largest = 0.0, difference = 0.0;
  for (std::size_t q = 0; q < two.size(); ++q) {
    largest = std::max(largest, std::abs(one[q]));
    difference = std::max(difference, std::abs(one[q] - two[q]));
  }
  std::printf("%s: max |1 rank - 2 ranks| = %.2e (fields up to %.2e)\n", name, difference, largest);
  EXPECT_LT(difference, 1e-10 * largest);
}

TEST(Ranks, PeriodicFftRunAgreesOnOneAndTwoRanks)
{
  FlowSetup setup = [](MPI_Comm comm) { return testing::abc_flow(comm, 16); };
  expect_same_on_one_and_two_ranks(setup, 8, 0.0625 / 16, "ABC fft 16^3");
}

/// The jet of whole_flows.hpp on 16 x 8 x 8 cells.
std::unique_ptr<NavierStokes> jet_in_a_box(MPI_Comm comm, bool outflow_by_velocity)
{
  return testing::jet_in_a_box(comm, {16, 8, 8}, outflow_by_velocity);
}

TEST(Ranks, KrylovRunWithTractionAndWallsAgreesOnOneAndTwoRanks)
{
  expect_same_on_one_and_two_ranks([](MPI_Comm comm) { return jet_in_a_box(comm, false); }, 5, 0.02,
                                   "jet in a box, krylov");
}

void expect_flux_conserved(bool outflow_by_velocity)
{
  auto fluid = jet_in_a_box(PETSC_COMM_WORLD, outflow_by_velocity);
  for (int s = 0; s < 5; ++s) {
    fluid->step(0.02);
    const double in = volume_flux(*fluid, PlaneRegion::rectangle(0, 0.0, {0, 0, 0}, {0, 1, 1}));
    const double out = volume_flux(*fluid, PlaneRegion::rectangle(0, 2.0, {0, 0, 0}, {0, 1, 1}));
    const double jet_disk = volume_flux(*fluid, PlaneRegion::disk(0, 0.0, {0, 0.5, 0.5}, 0.3));
    double walls = 0.0;
    for (int d = 1; d < 3; ++d)
      for (int upper = 0; upper < 2; ++upper)
        walls += std::abs(volume_flux(*fluid, PlaneRegion::rectangle(d, upper, {0, 0, 0}, {2, 1, 1})));
    EXPECT_GT(in, 0.0);
    EXPECT_NEAR(out, in, 1e-10 * in) << "step " << s;
    EXPECT_NEAR(jet_disk, in, 1e-2 * in) << "the jet lies inside its disk (up to the disk's sampled edge)";
    EXPECT_EQ(walls, 0.0);
    for (double x : {0.5, 0.8125, 1.37})
      EXPECT_NEAR(volume_flux(*fluid, PlaneRegion::rectangle(0, x, {0, 0, 0}, {0, 1, 1})), in, 1e-10 * in)
          << "plane x = " << x;
    if (world_rank() == 0 && s == 4)
      std::printf("closed box (%s outflow): in %.12f out %.12f, relative difference %.1e\n",
                  outflow_by_velocity ? "velocity" : "traction", in, out, std::abs(out - in) / in);
  }
}

TEST(Conservation, FluxInEqualsFluxOutWithATractionOutlet)
{
  expect_flux_conserved(false);
}
TEST(Conservation, FluxInEqualsFluxOutWithVelocityOnEverySide)
{
  expect_flux_conserved(true);
}

} // namespace
} // namespace ibvalve::fluid
