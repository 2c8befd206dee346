#pragma once
// Shared set-ups of the IB/FE verification tests (and measurements on them).
#include <cmath>
#include <functional>
#include <memory>
#include <vector>

#include <mpi.h>

#include "fe/mesh.hpp"
#include "fe/solid.hpp"
#include "fluid/navier_stokes.hpp"
#include "ib/ibfe.hpp"
#include "materials/law.hpp"
#include "materials/material.hpp"

namespace ibvalve::ib::testing {

/// True on rank 0 of the world (tests print their measurements once).
inline bool is_root()
{
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank == 0;
}

inline std::unique_ptr<fluid::NavierStokes> periodic_fluid(MPI_Comm comm, int cells, double rho, double mu)
{
  fluid::BoxGeometry box;
  box.cells = {cells, cells, cells};
  fluid::FluidSettings settings;
  settings.rho = rho;
  settings.mu = mu;
  auto f =
      std::make_unique<fluid::NavierStokes>(comm, box, fluid::BoundaryConditions::all_periodic(), settings);
  f->set_initial_condition(
      [](const fluid::Real3&, double) {
        return fluid::Real3{0.0, 0.0, 0.0};
      },
      nullptr, 0.0);
  return f;
}

/// Neo-Hookean W = mu/2 (I1 - 3) - mu ln J (P(I) = 0) plus a log volumetric penalty kappa/2 (ln J)^2.
inline std::shared_ptr<const materials::StrainEnergy> neo_hookean(double mu, double kappa)
{
  auto law =
      std::make_shared<materials::InvariantLaw>(materials::LawKind::neo_hookean, std::vector<double>{mu});
  return std::make_shared<materials::Material>(
      law, materials::VolumetricPenalty(materials::PenaltyKind::log, kappa));
}

inline std::vector<fe::BodyPart> one_part(const fe::Mesh& mesh,
                                          std::shared_ptr<const materials::StrainEnergy> law)
{
  fe::BodyPart part;
  part.name = "body";
  part.elements = mesh.group("body").elements;
  part.laws.push_back(std::move(law));
  return {part};
}

/// A neo-Hookean block (its volumetric penalty integrated at the element centre, as the valve's parts),
/// tethered, stretched isochorically by 1.1 along x about its centre, in a periodic box of 16^3 cells:
/// released, it relaxes. The coupled stability estimate's and the semi-implicit coupling's test case.
struct StretchedBlock {
  std::unique_ptr<fluid::NavierStokes> fluid;
  fe::Mesh mesh =
      fe::box_mesh(fe::CellShape::hexahedron, fe::Vec3(0.35, 0.4, 0.4), fe::Vec3(0.65, 0.6, 0.6), {6, 4, 4});
  std::unique_ptr<fe::SolidModel> solid;
  std::unique_ptr<ib::IbfeIntegrator> ibfe;

  explicit StretchedBlock(MPI_Comm comm, ib::CouplingKind coupling = ib::CouplingKind::explicit_midpoint,
                          double tolerance = 1e-3,
                          ib::StabilityEstimateKind estimate = ib::StabilityEstimateKind::acceleration)
  {
    fluid = periodic_fluid(comm, 16, 1.0, 0.1);
    fe::BodyPart part;
    part.name = "body";
    part.elements = mesh.group("body").elements;
    part.laws.push_back(
        std::make_shared<materials::InvariantLaw>(materials::LawKind::neo_hookean, std::vector<double>{1e4}));
    part.centre_laws.push_back(
        std::make_shared<materials::VolumetricPenalty>(materials::PenaltyKind::log, 1e6));
    solid = std::make_unique<fe::SolidModel>(mesh, std::vector<fe::BodyPart>{part}, 2, comm);
    ib::IbfeSettings settings;
    settings.tethers.push_back({"body", 1e5, 0.0});
    settings.coupling = coupling;
    settings.stability_estimate = estimate;
    settings.semi_implicit.tolerance = tolerance;
    ibfe = std::make_unique<ib::IbfeIntegrator>(*fluid, *solid, settings);
    std::vector<double> u(solid->num_dofs());
    const fe::Vec3 factor(1.1, 1.0 / std::sqrt(1.1), 1.0 / std::sqrt(1.1));
    for (std::size_t n = 0; n < mesh.num_nodes(); ++n)
      for (int d = 0; d < 3; ++d) u[3 * n + d] = (factor[d] - 1.0) * (mesh.nodes()[n][d] - 0.5);
    ibfe->set_displacement(u);
  }
};

/// Average pressure (at the fluid's pressure time) over the cells whose centre satisfies `select`.
inline double mean_pressure(const fluid::NavierStokes& fluid,
                            const std::function<bool(const fluid::Real3&)>& select)
{
  const fluid::StaggeredGrid& g = fluid.grid();
  fluid::StagArray a(g, fluid.state(), true);
  double sums[2] = {0.0, 0.0};
  for (PetscInt k = g.begin(2); k < g.begin(2) + g.count(2); ++k)
    for (PetscInt j = g.begin(1); j < g.begin(1) + g.count(1); ++j)
      for (PetscInt i = g.begin(0); i < g.begin(0) + g.count(0); ++i)
        if (select(g.cell_center(i, j, k))) {
          sums[0] += a(i, j, k, g.pressure_slot());
          sums[1] += 1.0;
        }
  MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_DOUBLE, MPI_SUM, g.comm());
  return sums[0] / sums[1];
}

/// Total fluid momentum rho sum_faces u h^3, per component.
inline Vec3 fluid_momentum(const fluid::NavierStokes& fluid)
{
  const fluid::StaggeredGrid& g = fluid.grid();
  fluid::StagArray a(g, fluid.state(), true);
  Vec3 m = Vec3::Zero();
  for (int d = 0; d < 3; ++d)
    for (PetscInt k = g.begin(2); k < g.face_end(d, 2); ++k)
      for (PetscInt j = g.begin(1); j < g.face_end(d, 1); ++j)
        for (PetscInt i = g.begin(0); i < g.face_end(d, 0); ++i) m[d] += a(i, j, k, g.face_slot(d));
  MPI_Allreduce(MPI_IN_PLACE, m.data(), 3, MPI_DOUBLE, MPI_SUM, g.comm());
  return m * fluid.settings().rho * g.cell_volume();
}

/// Pressure jump across a thick incompressible neo-Hookean spherical shell inflated by
/// r^3 = R^3 + a (radial equilibrium dsigma_rr/dr + 2 (sigma_rr - sigma_tt)/r = 0, sigma = -p I + mu B):
///   p_in - p_out = int_{r_i}^{r_o} 2 mu (lambda_t^2 - lambda_r^2) / r dr,
///   lambda_t = r / R, lambda_r = R^2 / r^2, R = (r^3 - a)^(1/3),
/// by composite Gauss-Legendre quadrature (the integrand is smooth).
inline double shell_pressure_jump(double mu, double R_inner, double R_outer, double a)
{
  const double r_i = std::cbrt(R_inner * R_inner * R_inner + a),
               r_o = std::cbrt(R_outer * R_outer * R_outer + a);
  const double x[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)}, w[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  const int pieces = 2000;
  const double step = (r_o - r_i) / pieces;
  double total = 0.0;
  for (int p = 0; p < pieces; ++p)
    for (int q = 0; q < 3; ++q) {
      const double r = r_i + step * (p + 0.5 + 0.5 * x[q]);
      const double R = std::cbrt(r * r * r - a);
      const double lt = r / R, lr = R * R / (r * r);
      total += 0.5 * step * w[q] * 2.0 * mu * (lt * lt - lr * lr) / r;
    }
  return total;
}

} // namespace ibvalve::ib::testing
