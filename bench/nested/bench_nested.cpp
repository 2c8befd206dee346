// Nested-grid benchmark (issue 9): the study's box, 8 x 8 x 14 cm, level 0 with 20 x 20 x 32 cells and one
// level of ratio 4 placed around an aortic-valve-sized bounding box ([-1.4, 1.4]^2 x [-1, 1.2] cm, margin 4
// fine cells), against one uniform grid of the finest spacing (80 x 80 x 128). For each it prints the
// composite cells, operator assembly time, CG + BoomerAMG set-up and solve times and iterations for a
// smooth right side (rtol 1e-8, Neumann sides), and peak memory over all ranks. Never fails on time.
//
//   mpiexec -n R bench_nested [divisor=1]   (divisor 2 halves every cell count per direction)
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <petscsys.h>

#include "fluid/composite_poisson.hpp"
#include "io/config.hpp"
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
  Vec b = ops.create_cell_vector(), x = ops.create_cell_vector();
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
  PETSC_CHECK(VecDestroy(&b));
  PETSC_CHECK(VecDestroy(&x));
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
    const std::string text = "[nested]\nratios = [4]\nmargins = [" + std::to_string(4 / divisor) + "]\n";
    const io::Config config = io::Config::validate(
        toml::parse(std::string_view{text}, std::string_view{"bench.toml"}), "bench.toml", nested_schema());
    const GridHierarchy nested =
        read_hierarchy(config, box, PhysicalBox{{-1.4, -1.4, -1.0}, {1.4, 1.4, 1.2}});
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
    run("uniform finest", GridHierarchy(uniform_box, {}), rank);
  }
  PetscFinalize();
  return 0;
}
