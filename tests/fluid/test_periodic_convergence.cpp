// Second-order convergence on periodic boxes (fft solver): an advected Taylor–Green vortex and the
// ABC flow of docs/reference.md, "Targets", on 16^3, 32^3 and 64^3 grids, with dt proportional to h,
// to a fixed short time. Orders are measured from the errors on successive grids.
#include <gtest/gtest.h>

#include "tests/fluid/exact_solutions.hpp"

namespace ibvalve::fluid {
namespace {

template <class Exact>
FieldErrors run_periodic(const Exact& exact, PetscInt n, double final_time, double dt_times_n,
                         SolverKind solver, ConvectionScheme scheme = ConvectionScheme::limited_upwind)
{
  BoxGeometry box;
  box.cells = {n, n, n};
  FluidSettings settings;
  settings.rho = 1.0;
  settings.mu = exact.rho * exact.nu;
  settings.solver = solver;
  settings.convection = scheme;
  NavierStokes fluid(PETSC_COMM_WORLD, box, BoundaryConditions::all_periodic(), settings);
  auto u = [&](const Real3& x, double t) { return exact.velocity(x, t); };
  auto p = [&](const Real3& x, double t) { return exact.pressure(x, t); };
  fluid.set_initial_condition(u, p, 0.0);
  const int steps = static_cast<int>(std::lround(final_time * static_cast<double>(n) / dt_times_n));
  const double dt = final_time / steps;
  double worst_divergence = 0.0;
  for (int s = 0; s < steps; ++s) {
    fluid.step(dt);
    // Discrete divergence relative to |u|/h after every step.
    worst_divergence =
        std::max(worst_divergence, max_divergence(fluid) / (max_velocity_magnitude(fluid) * n));
  }
  EXPECT_LT(worst_divergence, 1e-10) << "n = " << n;
  return field_errors(fluid, u, p, true);
}

template <class Exact>
void expect_second_order(const Exact& exact, const char* name, double final_time, double dt_times_n,
                         SolverKind solver)
{
  std::vector<FieldErrors> errors;
  const PetscInt grids[3] = {16, 32, 64};
  for (PetscInt n : grids) errors.push_back(run_periodic(exact, n, final_time, dt_times_n, solver));
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  for (std::size_t g = 0; g < 3; ++g) {
    if (rank == 0)
      std::printf("%s %3d^3: u L2 %.3e max %.3e | p L2 %.3e max %.3e\n", name, static_cast<int>(grids[g]),
                  errors[g].velocity_l2, errors[g].velocity_max, errors[g].pressure_l2,
                  errors[g].pressure_max);
    if (g == 0) continue;
    const double ou2 = testing::order(errors[g - 1].velocity_l2, errors[g].velocity_l2);
    const double oum = testing::order(errors[g - 1].velocity_max, errors[g].velocity_max);
    const double op2 = testing::order(errors[g - 1].pressure_l2, errors[g].pressure_l2);
    if (rank == 0) std::printf("%s orders: u L2 %.3f max %.3f | p L2 %.3f\n", name, ou2, oum, op2);
    EXPECT_GE(ou2, 1.9);
    EXPECT_GE(oum, 1.9);
    EXPECT_GE(op2, 1.8);
  }
}

TEST(PeriodicConvergence, AdvectedTaylorGreenIsSecondOrder)
{
  expect_second_order(testing::AdvectedTaylorGreen{}, "Taylor-Green", 0.0625, 0.0625, SolverKind::fft);
}

TEST(PeriodicConvergence, AbcFlowIsSecondOrder)
{
  expect_second_order(testing::AbcFlow{}, "ABC", 0.0625, 0.0625, SolverKind::fft);
}

} // namespace
} // namespace ibvalve::fluid
