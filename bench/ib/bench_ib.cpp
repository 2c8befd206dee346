// Time per coupled IB/FE step and its parts.
//
//   mpiexec -n R bench_ib [cells] [points] [steps] [projection]     (defaults: 32 10000 10 consistent)
//
// The structure is a slightly stretched neo-Hookean block of m^3 trilinear hexahedra with edges just
// under one grid cell, so each element carries 2 x 2 x 2 coupling points (spacing <= half a cell)
// and m = round(cbrt(points / 8)); it relaxes in a periodic box (FFT fluid solver, 64-bit doubles).
//
// `projection` is the L2 projections' mass, "consistent" (the default of every case) or "lumped" (no
// solves: what the consistent projections cost, against the accuracy they buy, docs/ib.md).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include <petscsys.h>

#include "base/logger.hpp"
#include "fe/mesh.hpp"
#include "fe/solid.hpp"
#include "fluid/navier_stokes.hpp"
#include "ib/ibfe.hpp"
#include "materials/law.hpp"
#include "materials/material.hpp"

using namespace ibvalve;

int main(int argc, char** argv)
{
  if (PetscInitialize(&argc, &argv, nullptr, nullptr) != 0) return 1;
  {
    const int cells = argc > 1 ? std::atoi(argv[1]) : 32;
    const double target = argc > 2 ? std::atof(argv[2]) : 1e4;
    const int steps = argc > 3 ? std::atoi(argv[3]) : 10;
    const std::string projection = argc > 4 ? argv[4] : "consistent";
    if (projection != "consistent" && projection != "lumped") {
      std::fprintf(stderr, "bench_ib: projection must be consistent or lumped, not '%s'\n",
                   projection.c_str());
      PetscFinalize();
      return 2;
    }
    int ranks = 1, rank = 0;
    MPI_Comm_size(PETSC_COMM_WORLD, &ranks);
    MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
    base::Logger::global().set_level(base::LogLevel::quiet);

    fluid::BoxGeometry box;
    box.cells = {cells, cells, cells};
    fluid::FluidSettings fs;
    fs.mu = 0.1;
    fluid::NavierStokes fluid(PETSC_COMM_WORLD, box, fluid::BoundaryConditions::all_periodic(), fs);
    fluid.set_initial_condition(
        [](const fluid::Real3&, double) {
          return fluid::Real3{0, 0, 0};
        },
        nullptr, 0.0);

    const int m = std::max(1, static_cast<int>(std::lround(std::cbrt(target / 8.0))));
    const double edge = 0.95 / cells, side = m * edge;
    const fe::Vec3 lo = fe::Vec3::Constant(0.5 - 0.5 * side), hi = fe::Vec3::Constant(0.5 + 0.5 * side);
    const fe::Mesh mesh = fe::box_mesh(fe::CellShape::hexahedron, lo, hi, {m, m, m});
    auto law = std::make_shared<materials::InvariantLaw>(materials::LawKind::neo_hookean,
                                                         std::vector<double>{100.0});
    fe::BodyPart part{"body",
                      mesh.group("body").elements,
                      {std::make_shared<materials::Material>(
                          law, materials::VolumetricPenalty(materials::PenaltyKind::log, 1000.0))}};
    fe::SolidModel solid(mesh, {part}, 2, PETSC_COMM_WORLD);
    ib::IbfeSettings settings;
    settings.velocity_projection = settings.force_projection =
        projection == "lumped" ? fe::MassKind::lumped : fe::MassKind::consistent;
    ib::IbfeIntegrator ibfe(fluid, solid, settings);
    std::vector<double> u(solid.num_dofs());
    for (std::size_t n = 0; n < mesh.num_nodes(); ++n) u[3 * n] = 0.04 * (mesh.nodes()[n][0] - 0.5);
    ibfe.set_displacement(u);
    const double dt = 0.5 * ibfe.stability_estimate().dt;
    ibfe.step(dt); // warm-up (first-step predictor of the fluid, rule caches)
    const ib::IbfeTimings before = ibfe.timings();
    for (int s = 0; s < steps; ++s) ibfe.step(dt);
    const ib::IbfeTimings& t = ibfe.timings();
    auto per_step = [&](double ib::IbfeTimings::*part) {
      double local = (t.*part - before.*part) / steps, worst = 0.0;
      MPI_Allreduce(&local, &worst, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD);
      return worst;
    };
    // Every rank reduces in the same order, then rank 0 prints.
    double figures[7];
    int i = 0;
    for (auto part : {&ib::IbfeTimings::total, &ib::IbfeTimings::fluid, &ib::IbfeTimings::interpolation,
                      &ib::IbfeTimings::projection, &ib::IbfeTimings::force, &ib::IbfeTimings::spreading,
                      &ib::IbfeTimings::points})
      figures[i++] = per_step(part);
    if (rank == 0) {
      std::printf("grid %d^3, %d rank(s), %zu elements, %zu coupling points, %d steps, %s projections\n",
                  cells, ranks, mesh.num_elements(), ibfe.coupling_point_count(), steps, projection.c_str());
      std::printf("  per coupled step (max over ranks), s: total %.4f | fluid %.4f | interpolation %.4f | "
                  "projection %.4f | force %.4f | spreading %.4f | points %.4f\n",
                  figures[0], figures[1], figures[2], figures[3], figures[4], figures[5], figures[6]);
    }
  }
  return PetscFinalize() != 0;
}
