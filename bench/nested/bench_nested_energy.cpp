// Kinetic energy and the largest speed of a free flow in the closed unit cube on nested levels at a
// high Reynolds number (prints figures only; docs/nested.md, "What is not done yet"). No-slip walls,
// level 1 [2/8, 5/8] x [3/8, 6/8] x [2/8, 4/8] (ratio 4) or one uniform grid of the finest spacing,
// started from the divergence-free 3D field of tests/fluid/test_nested_navier_stokes.cpp's manufactured
// flow at t = 0 with no body force: with walls and no forcing the kinetic energy can only fall, so a
// largest speed that jumps while it falls is a growing discrete mode. Each row: t, E/E0, max|u| and the
// centre of the face that holds it.
//   bench_nested_energy [nested|uniform] [limited|centred] [nu] [cfl] [end] [N0]
//   defaults: nested limited 1e-5 0.1 1.5 16 (dt = cfl x the finest spacing)
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>
#include <vector>

#include "fluid/nested_navier_stokes.hpp"
#include "io/petsc_check.hpp"

namespace {

using namespace ibvalve;
using namespace ibvalve::fluid;
constexpr double pi = std::numbers::pi;

Real3 initial_velocity(const Real3& x, double)
{
  const double g = 1.0 + 0.5 * std::sin(2.0 * x[2]), k = std::cos(x[0]);
  return {std::sin(pi * x[0]) * std::cos(pi * x[1]) * g,
          -std::cos(pi * x[0]) * std::sin(pi * x[1]) * g + std::sin(pi * x[1]) * std::cos(pi * x[2]) * k,
          -std::cos(pi * x[1]) * std::sin(pi * x[2]) * k};
}

GridHierarchy hierarchy(bool nested, PetscInt n0, PetscInt ratio)
{
  BoxGeometry box;
  const PetscInt n = nested ? n0 : n0 * ratio;
  box.cells = {n, n, n};
  box.periodic = {false, false, false};
  std::vector<FinerLevel> finer;
  if (nested) {
    IndexBox b;
    const Index3 lower{2, 3, 2}, upper{5, 6, 4};
    for (int d = 0; d < 3; ++d) {
      b.lower[d] = lower[d] * n0 * ratio / 8;
      b.upper[d] = upper[d] * n0 * ratio / 8;
    }
    finer.push_back(FinerLevel{ratio, {b}});
  }
  return GridHierarchy(box, finer);
}

/// The centre of the composite face with global index `global` (every rank gets it from its owner).
Real3 face_centre(const NestedNavierStokes& fluid, PetscInt global, MPI_Comm comm)
{
  PetscInt begin = 0, end = 0;
  PETSC_CHECK(VecGetOwnershipRange(fluid.velocity(), &begin, &end));
  Real3 local{0.0, 0.0, 0.0}, x{0.0, 0.0, 0.0};
  if (global >= begin && global < end) {
    const CompositeVelocity& velocity = fluid.composite_velocity();
    local = velocity.position(velocity.owned_keys()[static_cast<std::size_t>(global - begin)]);
  }
  MPI_Allreduce(local.data(), x.data(), 3, MPI_DOUBLE, MPI_SUM, comm);
  return x;
}

void run(bool nested, ConvectionScheme scheme, double nu, double cfl, double end, PetscInt n0)
{
  constexpr PetscInt ratio = 4;
  const GridHierarchy h = hierarchy(nested, n0, ratio);
  FluidSettings settings;
  settings.rho = 1.0;
  settings.mu = nu;
  settings.convection = scheme;
  NestedNavierStokes fluid(PETSC_COMM_WORLD, h, initial_velocity, settings);
  fluid.set_initial_condition(initial_velocity, ScalarFunction{}, 0.0);
  const double dt = cfl / static_cast<double>(n0 * ratio);
  const int steps = static_cast<int>(std::lround(end / dt));
  const double e0 = fluid.kinetic_energy();
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0)
    std::printf("# %s, %s convection, nu %g, dt %g (%d steps), N0 %d; t, E/E0, max|u|, at (x, y, z)\n",
                nested ? "nested (ratio 4)" : "uniform",
                scheme == ConvectionScheme::centered ? "centred" : "limited", nu, dt, steps,
                static_cast<int>(n0));
  for (int s = 1; s <= steps; ++s) {
    fluid.step(dt);
    if (s % std::max(1, steps / 32) != 0 && s != steps) continue;
    PetscInt at_max = 0, at_min = 0;
    double largest = 0.0, smallest = 0.0;
    PETSC_CHECK(VecMax(fluid.velocity(), &at_max, &largest));
    PETSC_CHECK(VecMin(fluid.velocity(), &at_min, &smallest));
    const PetscInt at = -smallest > largest ? at_min : at_max;
    const Real3 x = face_centre(fluid, at, PETSC_COMM_WORLD);
    const double e = fluid.kinetic_energy();
    if (rank == 0) {
      std::printf("%.4f %.6f %.4f (%.4f %.4f %.4f)\n", fluid.time(), e / e0, std::max(largest, -smallest),
                  x[0], x[1], x[2]);
      std::fflush(stdout);
    }
    if (!std::isfinite(e)) break;
  }
}

} // namespace

int main(int argc, char** argv)
{
  PETSC_CHECK(PetscInitialize(&argc, &argv, nullptr, nullptr));
  try {
    const std::vector<std::string> a(argv + 1, argv + argc);
    const auto arg = [&](std::size_t i, const char* fallback) {
      return i < a.size() ? a[i] : std::string(fallback);
    };
    const bool nested = arg(0, "nested") == "nested";
    const ConvectionScheme scheme =
        arg(1, "limited") == "centred" ? ConvectionScheme::centered : ConvectionScheme::limited_upwind;
    run(nested, scheme, std::stod(arg(2, "1e-5")), std::stod(arg(3, "0.1")), std::stod(arg(4, "1.5")),
        std::stoi(arg(5, "16")));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_nested_energy: %s\n", e.what());
    PetscFinalize();
    return 1;
  }
  PETSC_CHECK(PetscFinalize());
  return 0;
}
