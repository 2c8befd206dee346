// Nested-grid benchmark: the study's box, 8 x 8 x 14 cm, level 0 with 20 x 20 x 32 cells and one
// level of ratio 4 placed around an aortic-valve-sized bounding box ([-1.4, 1.4]^2 x [-1, 1.2] cm, margin 4
// fine cells), against one uniform grid of the finest spacing (80 x 80 x 128). For each it prints the
// composite cells, operator assembly time, CG + BoomerAMG set-up and solve times and iterations for a
// smooth right side (rtol 1e-8, Neumann sides), and peak memory over all ranks. Then the Navier–Stokes
// time step: NestedNavierStokes (fluid/nested_navier_stokes.hpp) on the two levels against the single-level
// NavierStokes (Krylov solver, BoomerAMG sub-solves, the model's default for walled boxes) on the uniform
// grid, both closed boxes with no-slip walls, rho = 1, mu = 0.04 (blood, CGS), a swirling flow of 50 cm/s
// driven by a body force, dt = 0.2 h_finest / 50 cm/s; set-up time, time per step and its parts,
// iterations and peak memory. Never fails on time.
//
//   mpiexec -n R bench_nested [divisor=1] [steps=4] [uniform=1]
//   (divisor 2 halves every cell count per direction; uniform=0 skips the uniform grid's time steps)
#include <fmt/format.h>
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <petscsys.h>

#include "fluid/composite_poisson.hpp"
#include "fluid/navier_stokes.hpp"
#include "fluid/nested_navier_stokes.hpp"
#include "io/key_binder.hpp"
#include "io/petsc_check.hpp"

using namespace ibvalve;
using namespace ibvalve::fluid;

namespace {

double seconds_since(std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void run(const char* name, const GridHierarchy& hierarchy, int rank)
{
  MPI_Barrier(PETSC_COMM_WORLD);
  auto start = std::chrono::steady_clock::now();
  const CompositeOperators ops(PETSC_COMM_WORLD, hierarchy, CoarseFineStencil::tangential_linear,
                               CompositeBoundary::neumann);
  const double assembly = seconds_since(start);
  const petsc::OwnedVec b = ops.create_cell_vector(), x = ops.create_cell_vector();
  // A smooth source with its mean removed by the solver (Neumann sides).
  ops.sample([](const Real3& p) { return std::cos(p[0]) * std::sin(0.7 * p[1]) * std::cos(0.4 * p[2]); }, b);
  PETSC_CHECK(VecPointwiseMult(b, b, ops.volumes()));
  start = std::chrono::steady_clock::now();
  const CompositePoissonSolver solver(ops, true, "bench_nested_", 1e-8);
  const PetscInt first = solver.solve(b, x); // includes the AMG set-up
  const double first_time = seconds_since(start);
  PETSC_CHECK(VecSet(x, 0.0));
  start = std::chrono::steady_clock::now();
  const PetscInt iterations = solver.solve(b, x);
  const double solve_time = seconds_since(start);
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  double peak = static_cast<double>(usage.ru_maxrss) / 1024.0;
  MPI_Allreduce(MPI_IN_PLACE, &peak, 1, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD);
  if (rank == 0) {
    std::printf("%s: %d levels, %d composite cells\n", name, hierarchy.levels(),
                static_cast<int>(ops.cells().size()));
    std::printf("  operator assembly          %.3f s\n", assembly);
    std::printf("  first solve (AMG set-up)   %.3f s, %d iterations\n", first_time, static_cast<int>(first));
    std::printf("  solve                      %.3f s, %d iterations\n", solve_time,
                static_cast<int>(iterations));
    std::printf("  peak memory so far         %.1f MB (all ranks)\n", peak);
  }
}

double peak_memory_mb()
{
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  double peak = static_cast<double>(usage.ru_maxrss) / 1024.0;
  MPI_Allreduce(MPI_IN_PLACE, &peak, 1, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD);
  return peak;
}

// A swirl about the z axis inside |r| < 2 cm, 50 cm/s at its edge: u(x) and the force that drives it.
Real3 swirl(const Real3& x, double)
{
  const double r2 = x[0] * x[0] + x[1] * x[1], envelope = std::exp(-r2 / 2.0 - x[2] * x[2] / 8.0);
  return {-25.0 * x[1] * envelope, 25.0 * x[0] * envelope, 0.0};
}

void nested_steps(const GridHierarchy& hierarchy, int steps, int rank)
{
  MPI_Barrier(PETSC_COMM_WORLD);
  auto start = std::chrono::steady_clock::now();
  FluidSettings settings;
  settings.convection = ConvectionScheme::centered; // second order on smooth flows (docs/nested.md)
  settings.rho = 1.0;
  settings.mu = 0.04;
  settings.rtol = 1e-10;
  NestedNavierStokes fluid(PETSC_COMM_WORLD, hierarchy, VelocityFunction{}, settings);
  fluid.set_initial_condition(swirl, {}, 0.0);
  fluid.set_body_force(
      [](const Real3& x, double t) {
        const Real3 u = swirl(x, t);
        return Real3{0.5 * u[0], 0.5 * u[1], 0.0};
      },
      0.0);
  const double setup = seconds_since(start);
  const double dt = 0.2 * hierarchy.h(hierarchy.finest(), 0) / 50.0;
  fluid.step(dt); // the first step (Heun: two solves, AMG set-ups)
  const StepStatistics first = fluid.statistics();
  start = std::chrono::steady_clock::now();
  PetscInt velocity = 0, pressure = 0;
  for (int s = 0; s < steps; ++s) {
    fluid.step(dt);
    velocity = std::max(velocity, fluid.velocity_iterations());
    pressure = std::max(pressure, fluid.pressure_iterations());
  }
  const double per_step = seconds_since(start) / steps;
  const StepStatistics& s = fluid.statistics();
  const auto divergence = fluid.max_divergence_by_level();
  const double peak = peak_memory_mb();
  PetscInt faces = 0;
  PETSC_CHECK(VecGetSize(fluid.velocity(), &faces));
  if (rank == 0) {
    std::printf("NestedNavierStokes, %d levels, %d composite cells, %d composite faces\n", hierarchy.levels(),
                static_cast<int>(fluid.operators().cells().size()), static_cast<int>(faces));
    std::printf("  set-up (operators, ghost maps)  %.3f s\n", setup);
    std::printf("  first step (Heun, AMG set-ups)  %.3f s\n", first.total);
    std::printf("  time per step                   %.3f s (convection %.3f, viscous %.3f, projection %.3f)\n",
                per_step, (s.convection - first.convection) / steps, (s.viscous - first.viscous) / steps,
                (s.pressure - first.pressure) / steps);
    std::printf("  iterations per step             viscous %d (GMRES + BoomerAMG), projection %d (GMRES + "
                "BoomerAMG)\n",
                static_cast<int>(velocity), static_cast<int>(pressure));
    std::printf("  max |D u| per level            ");
    for (const double d : divergence) std::printf(" %.1e", d);
    std::printf("\n  peak memory so far              %.1f MB (all ranks)\n", peak);
  }
}

void uniform_steps(const BoxGeometry& box, int steps, int rank)
{
  MPI_Barrier(PETSC_COMM_WORLD);
  auto start = std::chrono::steady_clock::now();
  BoundaryConditions bc;
  for (int side = 0; side < 6; ++side) bc.side(side).kind = SideKind::velocity;
  FluidSettings settings;
  settings.rho = 1.0;
  settings.mu = 0.04;
  settings.solver = SolverKind::krylov;
  settings.subsolver = SubsolverKind::amg;
  settings.rtol = 1e-10;
  NavierStokes fluid(PETSC_COMM_WORLD, box, bc, settings);
  fluid.set_initial_condition(
      swirl, [](const Real3&, double) { return 0.0; }, 0.0);
  fluid.set_body_force(
      [](const Real3& x, double t) {
        const Real3 u = swirl(x, t);
        return Real3{0.5 * u[0], 0.5 * u[1], 0.0};
      },
      0.0);
  const double setup = seconds_since(start);
  const double dt = 0.2 * box.spacing(0) / 50.0;
  start = std::chrono::steady_clock::now();
  fluid.step(dt);
  const double first = seconds_since(start);
  start = std::chrono::steady_clock::now();
  PetscInt iterations = 0;
  for (int s = 0; s < steps; ++s) {
    fluid.step(dt);
    iterations = std::max(iterations, fluid.last_solve().iterations);
  }
  const double per_step = seconds_since(start) / steps;
  const double peak = peak_memory_mb();
  if (rank == 0) {
    std::printf("NavierStokes (one level, Krylov + AMG sub-solves), %d x %d x %d cells\n",
                static_cast<int>(box.cells[0]), static_cast<int>(box.cells[1]),
                static_cast<int>(box.cells[2]));
    std::printf("  set-up                          %.3f s\n", setup);
    std::printf("  first step                      %.3f s\n", first);
    std::printf("  time per step                   %.3f s\n", per_step);
    std::printf("  FGMRES iterations per step      %d\n", static_cast<int>(iterations));
    std::printf("  peak memory so far              %.1f MB (all ranks)\n", peak);
  }
}

} // namespace

int main(int argc, char** argv)
{
  if (PetscInitialize(&argc, &argv, nullptr, nullptr) != 0) return 1;
  {
    const PetscInt divisor = argc > 1 ? std::atoi(argv[1]) : 1;
    int rank = 0, size = 1;
    MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
    MPI_Comm_size(PETSC_COMM_WORLD, &size);
    BoxGeometry box;
    box.lower = {-4.0, -4.0, -7.0};
    box.upper = {4.0, 4.0, 7.0};
    box.cells = {20 / divisor, 20 / divisor, 32 / divisor};
    box.periodic = {false, false, false};
    const std::string text = fmt::format("[nested]\nratios = [4]\nmargins = [{}]\n", 4 / divisor);
    io::Schema schema;
    io::KeyBinder declaring(schema);
    NestedKeys unused;
    fluid::bind(declaring, unused);
    const io::Config config = io::Config::validate(
        toml::parse(std::string_view{text}, std::string_view{"bench.toml"}), "bench.toml", schema);
    io::KeyBinder keys(config);
    NestedKeys k;
    fluid::bind(keys, k);
    const GridHierarchy nested =
        read_hierarchy(keys, k, box, PhysicalBox{{-1.4, -1.4, -1.0}, {1.4, 1.4, 1.2}});
    if (rank == 0) {
      const IndexBox& fine = nested.boxes(1)[0];
      std::printf(
          "nested-grid benchmark on %d ranks: level 0 %d x %d x %d, level 1 (ratio 4) box %d x %d x %d\n",
          size, static_cast<int>(box.cells[0]), static_cast<int>(box.cells[1]),
          static_cast<int>(box.cells[2]), static_cast<int>(fine.cells(0)), static_cast<int>(fine.cells(1)),
          static_cast<int>(fine.cells(2)));
    }
    run("two levels", nested, rank);
    BoxGeometry uniform_box = box;
    for (int d = 0; d < 3; ++d) uniform_box.cells[d] *= 4;
    // The nested time steps before anything on the uniform grid, so their peak memory is their own.
    const int steps = argc > 2 ? std::atoi(argv[2]) : 4;
    const bool uniform = argc > 3 ? std::atoi(argv[3]) != 0 : true;
    nested_steps(nested, steps, rank);
    run("uniform finest", GridHierarchy(uniform_box, {}), rank);
    if (uniform) uniform_steps(uniform_box, steps, rank);
  }
  PetscFinalize();
  return 0;
}
