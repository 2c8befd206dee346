// fe/ benchmark: nodal-force assembly throughput (elements per second), tangent assembly and the
// smallest quadrature-point J (the figure a coupled step adds to diagnostics.csv), for each
// law of materials/ (with a log volumetric penalty), on hexahedra and tetrahedra. The mesh is
// replicated and the elements split over the ranks (docs/fe.md): run under `mpiexec -n 1` and `-n 2`
// and compare. Prints figures only (median of several repetitions), never fails on time.
//   bench_fe [cells per direction, default 20]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <vector>

#include <petscsys.h>

#include "fe/solid.hpp"
#include "materials/law.hpp"
#include "materials/material.hpp"
#include "materials/settings.hpp"

using namespace ibvalve;

namespace {

double median(std::vector<double> v)
{
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

} // namespace

int main(int argc, char** argv)
{
  int n = 20;
  if (argc > 1) n = std::atoi(argv[1]);
  PetscInitialize(&argc, &argv, nullptr, nullptr);
  int size = 1, rank = 0;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  struct LawCase {
    const char* label;
    materials::LawKind kind;
    std::vector<double> user_values;
  };
  const std::vector<LawCase> laws{
      {"neo-Hookean", materials::LawKind::neo_hookean, {10.0}},
      {"W1", materials::LawKind::W1, materials::find_preset("zhu2021-W1")->values},
      {"W2", materials::LawKind::W2, materials::find_preset("zhu2021-W2")->values},
      {"W3", materials::LawKind::W3, materials::find_preset("zhu2021-W3")->values},
      {"HGO", materials::LawKind::hgo, materials::find_preset("holzapfel2000-media")->values}};
  if (rank == 0)
    std::printf("fe assembly benchmark: %d rank(s), box of %d^3 cells, quadrature degree 2, log penalty\n",
                size, n);
  if (rank == 0)
    std::printf("%-12s %-6s %9s %6s %14s %14s %16s %12s\n", "law", "cells", "elements", "points",
                "forces [ms]", "Melem/s", "tangent [ms]", "min J [ms]");
  for (fe::CellShape shape : {fe::CellShape::hexahedron, fe::CellShape::tetrahedron}) {
    const int cells = shape == fe::CellShape::hexahedron ? n : std::max(1, n / 2);
    fe::Mesh mesh = fe::box_mesh(shape, fe::Vec3(0, 0, 0), fe::Vec3(1, 1, 1), {cells, cells, cells});
    std::vector<double> u(3 * mesh.num_nodes());
    std::mt19937 generator(5);
    std::uniform_real_distribution<double> noise(-0.01 / cells, 0.01 / cells);
    for (std::size_t a = 0; a < mesh.num_nodes(); ++a) {
      const fe::Vec3& X = mesh.nodes()[a];
      u[3 * a] = 0.1 * X[0] + noise(generator);
      u[3 * a + 1] = -0.03 * X[1] + noise(generator);
      u[3 * a + 2] = 0.02 * X[0] * X[2] + noise(generator);
    }
    std::vector<double> forces(u.size());
    for (const LawCase& law : laws) {
      auto invariant =
          std::make_shared<materials::InvariantLaw>(law.kind, materials::to_cgs(law.kind, law.user_values));
      auto material = std::make_shared<materials::Material>(
          invariant, materials::VolumetricPenalty(materials::PenaltyKind::log, 1e6));
      fe::SolidModel solid(mesh, {fe::BodyPart{"body", mesh.group("body").elements, {material}}}, 2,
                           PETSC_COMM_WORLD);
      materials::FiberFrame frame;
      frame.f0 = fe::Vec3(1, 1, 0).normalized();
      frame.s0 = fe::Vec3(1, -1, 0).normalized();
      solid.set_fibers(std::vector<materials::FiberFrame>(mesh.num_elements(), frame));
      std::vector<double> force_times, tangent_times, jacobian_times;
      fe::NodalSystem system(mesh, 3, PETSC_COMM_WORLD);
      const petsc::OwnedMat K = system.create_matrix();
      for (int repeat = 0; repeat < 5; ++repeat) {
        MPI_Barrier(PETSC_COMM_WORLD);
        auto start = std::chrono::steady_clock::now();
        solid.forces(u, forces);
        force_times.push_back(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        MPI_Barrier(PETSC_COMM_WORLD);
        start = std::chrono::steady_clock::now();
        MatZeroEntries(K);
        solid.add_stiffness(u, system, K);
        MatAssemblyBegin(K, MAT_FINAL_ASSEMBLY);
        MatAssemblyEnd(K, MAT_FINAL_ASSEMBLY);
        tangent_times.push_back(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        MPI_Barrier(PETSC_COMM_WORLD);
        start = std::chrono::steady_clock::now();
        (void)solid.smallest_point_jacobian(u); // diagnostics.csv's smallest_J, once a coupled step
        jacobian_times.push_back(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      }
      const double force_time = median(force_times), tangent_time = median(tangent_times);
      if (rank == 0)
        std::printf("%-12s %-6s %9zu %6d %14.2f %14.3f %16.2f %12.3f\n", law.label,
                    mesh.type().name().c_str(), mesh.num_elements(), solid.quadrature().points_per_element(),
                    1e3 * force_time, mesh.num_elements() / force_time / 1e6, 1e3 * tangent_time,
                    1e3 * median(jacobian_times));
    }
  }
  PetscFinalize();
  return 0;
}
