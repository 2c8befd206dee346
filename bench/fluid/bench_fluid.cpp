// Fluid benchmark (docs/reference.md, "Targets"): the 3-D periodic ABC flow with mean advection on N^3
// cells, rho = 1, mu = 0.01, dt = 0.0625/N; or (flow = cavity) a walled box: the unit cube with
// velocity sides, the lid z = 1 moving in x (16 x(1-x) y(1-y)), started from a wall-compatible swirl,
// dt = 0.25/N; or (flow = valve) the valve case's kind of sides: a 3.5 x 3.5 x 3.5 cm box of blood
// (rho 1, mu 0.04 P) with walls in x and y, and z sides that are traction sides in a disk of radius
// 1.3 cm about the axis and walls around it (walled in part), with backflow stabilization (beta 1),
// 10 mmHg at the inlet disk and 0 at the outlet, from rest, dt = 2e-5 s x 28/N (the default valve case's
// viscous number nu dt/h^2 on its 28 cells across). Prints the time per step (excluding set-up: (T(2S) -
// T(S))/S) and its parts, solver iterations, peak memory over all ranks (getrusage), and the max-norm
// velocity and pressure errors against the exact solution (ABC). Never fails on time.
//
//   mpiexec -n R bench_fluid [N=64] [solver=fft|krylov|krylov-fft] [S=10] [convection=limited|centered]
//                            [flow=abc|cavity|valve]
// krylov-fft is the Krylov solver with the FFTW transform sub-solves (fluid.subsolver = "fft").
#include <sys/resource.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>

#include <petscsys.h>

#include "fluid/navier_stokes.hpp"
#include "fluid/queries.hpp"
#include "tests/fluid/exact_solutions.hpp"

using namespace ibvalve::fluid;

namespace {

/// The box's sides: periodic (ABC), the lid-driven cavity's velocity sides, or the valve case's kind.
void set_sides(bool cavity, bool valve, BoxGeometry& box, BoundaryConditions& bc)
{
  if (cavity) {
    box.periodic = {false, false, false};
    for (int side = 0; side < 6; ++side) bc.side(side).kind = SideKind::velocity;
    bc.side(2, 1).velocity = [](const Real3& x, double) {
      return Real3{16.0 * x[0] * (1.0 - x[0]) * x[1] * (1.0 - x[1]), 0.0, 0.0};
    };
  }
  if (valve) {
    const double length = 3.5, radius = 1.3, inlet = 10.0 * 1333.22;
    box.lower = {-0.5 * length, -0.5 * length, 0.0};
    box.upper = {0.5 * length, 0.5 * length, length};
    box.periodic = {false, false, false};
    for (int side = 0; side < 4; ++side) bc.side(side).kind = SideKind::velocity;
    for (int upper = 0; upper < 2; ++upper) {
      BoundarySide& side = bc.side(2, upper);
      side.kind = SideKind::traction;
      side.wall = [radius](const Real3& x) { return x[0] * x[0] + x[1] * x[1] > radius * radius; };
      side.backflow = 1.0;
      if (upper == 0) side.pressure = [inlet](const Real3&, double) { return inlet; };
    }
  }
}

} // namespace

int main(int argc, char** argv)
{
  if (PetscInitialize(&argc, &argv, nullptr, nullptr) != 0) return 1;
  {
    const PetscInt n = argc > 1 ? std::atoi(argv[1]) : 64;
    const std::string solver_name = argc > 2 ? argv[2] : "fft";
    const int s = argc > 3 ? std::atoi(argv[3]) : 10;
    const std::string scheme = argc > 4 ? argv[4] : "limited";
    const std::string flow = argc > 5 ? argv[5] : "abc";
    const bool cavity = flow == "cavity", valve = flow == "valve";
    int rank = 0, size = 1;
    MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
    MPI_Comm_size(PETSC_COMM_WORLD, &size);

    BoxGeometry box;
    box.cells = {n, n, n};
    BoundaryConditions bc;
    set_sides(cavity, valve, box, bc);
    FluidSettings settings;
    settings.mu = valve ? 0.04 : 0.01;
    settings.solver = solver_name == "fft" ? SolverKind::fft : SolverKind::krylov;
    settings.subsolver = solver_name == "krylov-fft" ? SubsolverKind::fft : SubsolverKind::amg;
    settings.rtol = valve ? 1e-10 : 1e-8; // the valve case solves to fluid.rtol = 1e-10
    settings.convection =
        scheme == "centered" ? ConvectionScheme::centered : ConvectionScheme::limited_upwind;
    ibvalve::fluid::testing::AbcFlow exact;
    auto u = [&](const Real3& x, double t) {
      if (valve) return Real3{0.0, 0.0, 0.0};
      if (!cavity) return exact.velocity(x, t);
      const double pi = std::numbers::pi, sx = std::sin(pi * x[0]), sy = std::sin(pi * x[1]);
      return Real3{sx * sx * std::sin(2.0 * pi * x[1]) * sy, -std::sin(2.0 * pi * x[0]) * sy * sy * sx, 0.0};
    };
    auto p = [&](const Real3& x, double t) { return cavity || valve ? 0.0 : exact.pressure(x, t); };
    const double dt =
        valve ? 2e-5 * 28.0 / static_cast<double>(n) : (cavity ? 0.25 : 0.0625) / static_cast<double>(n);
    const double setup_start = MPI_Wtime();
    NavierStokes fluid(PETSC_COMM_WORLD, box, bc, settings);
    fluid.set_initial_condition(u, p, 0.0);
    for (int i = 0; i < s; ++i) fluid.step(dt);
    const double setup = MPI_Wtime() - setup_start;
    const StepStatistics first = fluid.statistics();
    MPI_Barrier(PETSC_COMM_WORLD);
    const double t0 = MPI_Wtime();
    for (int i = 0; i < s; ++i) fluid.step(dt);
    MPI_Barrier(PETSC_COMM_WORLD);
    const double per_step = (MPI_Wtime() - t0) / s;
    const StepStatistics all = fluid.statistics();
    auto part = [&](double StepStatistics::*field) {
      double v = (all.*field - first.*field) / s;
      MPI_Allreduce(MPI_IN_PLACE, &v, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD);
      return v;
    };
    const FieldErrors errors = field_errors(fluid, u, p, true);
    const double divergence = max_divergence(fluid);
    const double speed = max_velocity_magnitude(fluid), energy = kinetic_energy(fluid);
    struct rusage usage;
    getrusage(RUSAGE_SELF, &usage);
    double peak_mb = static_cast<double>(usage.ru_maxrss) / 1024.0, peak_total = peak_mb;
    MPI_Allreduce(MPI_IN_PLACE, &peak_total, 1, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD);
    if (rank == 0) {
      std::printf("fluid %s %d^3, %d rank%s, solver %s, convection %s, dt %.3e, %d + %d steps\n",
                  valve    ? "valve sides"
                  : cavity ? "cavity"
                           : "ABC",
                  static_cast<int>(n), size, size > 1 ? "s" : "", solver_name.c_str(), scheme.c_str(), dt, s,
                  s);
      std::printf("  time per step      %.4f s   (set-up + first %d steps %.2f s)\n", per_step, s, setup);
      std::printf("    convection       %.4f s\n", part(&StepStatistics::convection));
      std::printf("    viscous solve    %.4f s\n", part(&StepStatistics::viscous));
      std::printf("    pressure solve   %.4f s\n", part(&StepStatistics::pressure));
      std::printf("    halo exchange    %.4f s\n", part(&StepStatistics::halo));
      std::printf("  solver iterations  %.2f per step\n",
                  static_cast<double>(all.solver_iterations - first.solver_iterations) / s);
      std::printf("  peak memory        %.1f MB (all ranks), %.1f MB rank 0\n", peak_total, peak_mb);
      if (cavity || valve)
        std::printf("  at t=%.4f  max |u| %.4f, kinetic energy %.6e; max |div u| %.2e\n", fluid.time(), speed,
                    energy, divergence);
      else
        std::printf("  errors at t=%.4f  u max %.3e  p max %.3e (u L2 %.3e, p L2 %.3e); max |div u| %.2e\n",
                    fluid.time(), errors.velocity_max, errors.pressure_max, errors.velocity_l2,
                    errors.pressure_l2, divergence);
    } else {
      part(&StepStatistics::convection);
      part(&StepStatistics::viscous);
      part(&StepStatistics::pressure);
      part(&StepStatistics::halo);
    }
  }
  PetscFinalize();
  return 0;
}
