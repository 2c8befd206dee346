// 02_ib_block_relaxing: an elastic structure in fluid, coupled by the IB/FE method.
//
// Shows the pieces of a coupled run and how they fit together:
//   fe::box_mesh          a small block of trilinear hexahedra (fe/mesh.hpp)
//   materials::...        a neo-Hookean law plus a volumetric penalty (materials/settings.hpp)
//   fe::SolidModel        the block's elastic forces from that material (fe/solid.hpp)
//   fluid::NavierStokes   a box with no-slip walls on every side (fluid/navier_stokes.hpp)
//   ib::UniformFluid      the fluid as the IB method sees it (ib/eulerian_fluid.hpp)
//   ib::IbfeIntegrator    fluid and structure advanced together (ib/ibfe.hpp)
// The block (0.3 x 0.2 x 0.2 cm, in a 1 cm box of a fluid 10 times as viscous as water) starts
// stretched by 25 % along x and shrunk by 1/sqrt(1.25) across, a volume-preserving stretch, at rest,
// and is released: its elastic forces push the fluid, the fluid carries the block back towards its
// reference shape and viscosity takes up the energy.
//
// Prints (through the library's log) the time-step estimate of the explicit coupling, then every 10
// steps the volume change V/V0 - 1 and the largest node displacement. Exits 1 unless the volume stays
// within 1 % (the fluid's velocity is discretely divergence free, but the velocity the structure gets
// from it is interpolated by the kernel, divergence free only to O(h^2)) and the largest displacement
// has fallen below a quarter of its start (the block relaxes).
//
//   mpiexec -n 1 build/examples/api/02_ib_block_relaxing
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <petscsys.h>

#include "fe/mesh.hpp"
#include "fe/solid.hpp"
#include "fluid/navier_stokes.hpp"
#include "ib/eulerian_fluid.hpp"
#include "ib/ibfe.hpp"
#include "materials/settings.hpp"

using namespace ibvalve;

namespace {

/// The largest |chi - X| over the nodes, cm.
double largest_displacement(const std::vector<double>& u)
{
  double largest = 0.0;
  for (std::size_t n = 0; n < u.size() / 3; ++n)
    largest = std::max(largest, std::hypot(u[3 * n], u[3 * n + 1], u[3 * n + 2]));
  return largest;
}

} // namespace

int main(int argc, char** argv)
{
  if (PetscInitialize(&argc, &argv, nullptr, nullptr) != 0) return 1;
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  bool ok = false;
  {
    // The fluid: the unit box on 16^3 cells with walls (velocity sides, zero velocity) on all six
    // sides; the Krylov Stokes solver handles walls, the FFT one only periodic boxes.
    fluid::BoxGeometry box;
    box.cells = {16, 16, 16};
    box.periodic = {false, false, false};
    fluid::BoundaryConditions walls;
    for (int side = 0; side < 6; ++side) walls.side(side).kind = fluid::SideKind::velocity;
    fluid::FluidSettings viscous;
    viscous.rho = 1.0; // g/cm^3
    viscous.mu = 0.1;  // g/(cm s)
    viscous.solver = fluid::SolverKind::krylov;
    fluid::NavierStokes fluid(PETSC_COMM_WORLD, box, walls, viscous);
    fluid.set_initial_condition(
        [](const fluid::Real3&, double) {
          return fluid::Real3{0.0, 0.0, 0.0};
        },
        nullptr, 0.0);

    // The structure: 6 x 4 x 4 hexahedra (elements about 0.8 grid cells), one body part of the mesh's
    // volume group "body", integrated with the degree-2 Gauss rule.
    const fe::Mesh mesh = fe::box_mesh(fe::CellShape::hexahedron, fe::Vec3(0.35, 0.4, 0.4),
                                       fe::Vec3(0.65, 0.6, 0.6), {6, 4, 4});
    materials::MaterialSettings material; // W = mu/2 (I1 - 3) + kappa/2 (ln J)^2 (+ the stress-free term)
    material.law = materials::LawKind::neo_hookean;
    material.parameters = {100.0}; // mu, dyn/cm^2 (CGS inside; case files take kPa)
    material.penalty = materials::PenaltyKind::log;
    material.bulk_modulus = 1000.0; // kappa, dyn/cm^2
    fe::BodyPart block{"body", mesh.group("body").elements, {material.build()}};
    const fe::SolidModel solid(mesh, {block}, 2, PETSC_COMM_WORLD);

    // The coupling, with the default kernel and consistent L2 projections.
    ib::UniformFluid eulerian(fluid);
    ib::IbfeIntegrator ibfe(eulerian, solid, ib::IbfeSettings{});

    // Released from an isochoric stretch about the block's centre (0.5, 0.5, 0.5).
    const double stretch = 1.25, across = 1.0 / std::sqrt(stretch);
    std::vector<double> u(solid.num_dofs());
    for (std::size_t n = 0; n < mesh.num_nodes(); ++n) {
      const fe::Vec3 X = mesh.nodes()[n];
      u[3 * n] = (stretch - 1.0) * (X[0] - 0.5);
      u[3 * n + 1] = (across - 1.0) * (X[1] - 0.5);
      u[3 * n + 2] = (across - 1.0) * (X[2] - 0.5);
    }
    ibfe.set_displacement(u);

    // The coupling is explicit: its first step logs the stable time-step estimate (ib/ibfe.hpp,
    // StabilityEstimate), 2.6e-3 s here.
    const double dt = 2e-3; // s
    const double V0 = mesh.volume(), start = largest_displacement(ibfe.displacement());
    double worst_volume = 0.0;
    if (rank == 0) std::printf("     t [s]   V/V0 - 1   largest displacement [cm]\n");
    for (int s = 1; s <= 60; ++s) {
      ibfe.step(dt);
      const double volume_change = ibfe.volume() / V0 - 1.0; // the mesh is on every rank: no MPI
      worst_volume = std::max(worst_volume, std::abs(volume_change));
      if (rank == 0 && s % 10 == 0)
        std::printf("  %8.3f  %+9.2e   %.4f\n", ibfe.time(), volume_change,
                    largest_displacement(ibfe.displacement()));
    }
    const double end = largest_displacement(ibfe.displacement());
    ok = worst_volume < 0.01 && end < 0.25 * start;
    if (rank == 0)
      std::printf("largest |V/V0 - 1| %.2e (bound 1e-2); displacement %.4f -> %.4f cm (bound x 0.25): %s\n",
                  worst_volume, start, end, ok ? "relaxed" : "FAILED");
  }
  PetscFinalize();
  return ok ? 0 : 1;
}
