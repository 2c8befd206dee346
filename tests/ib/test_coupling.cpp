// The coupling points and the L2 projections: the rule follows the deformed element size, the points'
// weights integrate the reference volume, and the velocity interpolated at the points and projected
// to the nodes reproduces a linear velocity field exactly with the consistent mass (a constant one
// with the lumped mass).
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include <gtest/gtest.h>

#include "fe/mesh.hpp"
#include "ib/coupling_points.hpp"
#include "ibfe_cases.hpp"

using namespace ibvalve;
using namespace ibvalve::ib::testing;

TEST(CouplingPoints, RuleFollowsTheDeformedElementSizeAndWeightsIntegrateTheVolume)
{
  const fe::Mesh mesh =
      fe::box_mesh(fe::CellShape::hexahedron, fe::Vec3(0, 0, 0), fe::Vec3(0.4, 0.2, 0.2), {4, 2, 2});
  ib::CouplingPoints points(mesh, {});
  std::vector<ib::Vec3> x(mesh.nodes().begin(), mesh.nodes().end());
  const double h = 0.05; // element edges 0.1 = 2 cells: 4 points per direction at spacing <= h/2
  points.update(x, h);
  EXPECT_EQ(points.points_per_direction(0), 4);
  EXPECT_EQ(points.size(), mesh.num_elements() * 64);
  // Stretch x by 1.6: edges 0.16 = 3.2 cells -> 7 points per direction.
  for (auto& p : x) p[0] *= 1.6;
  points.update(x, h);
  EXPECT_EQ(points.points_per_direction(0), 7);
  double volume = 0.0;
  for (std::size_t q = 0; q < points.size(); ++q) volume += points.weight(q);
  EXPECT_NEAR(volume, 0.4 * 0.2 * 0.2, 1e-14);
  // Points sit at the current positions (x stretched), weights stay referential.
  double largest_x = 0.0;
  for (const auto& p : points.positions()) largest_x = std::max(largest_x, p[0]);
  EXPECT_GT(largest_x, 0.4);
  EXPECT_LT(largest_x, 0.64);
}

// A rank places only the elements it may need (ib/ibfe.cpp): the flagged elements' points are where a
// full placement puts them, and each element's points are the range first_point(e) .. first_point(e+1).
TEST(CouplingPoints, PlacingSomeElementsPlacesTheirPointsAsAFullPlacementDoes)
{
  const fe::Mesh mesh =
      fe::box_mesh(fe::CellShape::hexahedron, fe::Vec3(0, 0, 0), fe::Vec3(0.4, 0.2, 0.2), {4, 2, 2});
  std::vector<ib::Vec3> x(mesh.nodes().begin(), mesh.nodes().end());
  for (auto& p : x) p += ib::Vec3(0.01 * std::sin(7.0 * p[1]), 0.02 * p[0] * p[2], 0.0);
  ib::CouplingPoints all(mesh, {}), some(mesh, {});
  const double h = 0.07;
  all.update(x, h);
  std::vector<std::uint8_t> placed(mesh.num_elements(), 0);
  for (std::size_t e = 0; e < placed.size(); e += 3) placed[e] = 1;
  some.update(x, h, placed);
  ASSERT_EQ(all.size(), some.size());
  EXPECT_EQ(some.first_point(0), 0u);
  EXPECT_EQ(some.first_point(mesh.num_elements()), some.size());
  for (std::size_t e = 0; e < mesh.num_elements(); ++e)
    for (std::size_t q = some.first_point(e); q < some.first_point(e + 1); ++q) {
      EXPECT_EQ(some.element(q), e);
      if (placed[e] != 0) {
        EXPECT_EQ(some.positions()[q], all.positions()[q]);
      }
    }
  EXPECT_THROW(some.update(x, h, std::vector<std::uint8_t>(2, 1)), std::invalid_argument);
}

TEST(CouplingPoints, TetrahedraGetConicalRulesThatIntegrateTheVolume)
{
  const fe::Mesh mesh =
      fe::box_mesh(fe::CellShape::tetrahedron, fe::Vec3(0, 0, 0), fe::Vec3(0.2, 0.2, 0.2), {2, 2, 2});
  ib::CouplingPoints points(mesh, {});
  std::vector<ib::Vec3> x(mesh.nodes().begin(), mesh.nodes().end());
  points.update(x, 0.05);
  double volume = 0.0;
  for (std::size_t q = 0; q < points.size(); ++q) volume += points.weight(q);
  EXPECT_NEAR(volume, 0.008, 1e-15);
  EXPECT_GE(points.points_per_direction(0), 4);
}

TEST(Projection, LinearVelocityIsReproducedAtTheNodesByTheConsistentProjection)
{
  // A walled box holding u = a + B x; the structure sits well inside (kernel away from the walls).
  fluid::BoxGeometry box;
  box.cells = {16, 16, 16};
  box.periodic = {false, false, false};
  fluid::BoundaryConditions bc;
  for (int s = 0; s < 6; ++s) bc.side(s).kind = fluid::SideKind::velocity;
  fluid::FluidSettings settings;
  settings.solver = fluid::SolverKind::krylov;
  fluid::NavierStokes fluid(PETSC_COMM_WORLD, box, bc, settings);
  const Eigen::Matrix3d B{{0.3, -1.2, 2.0}, {0.7, 0.1, -0.4}, {-1.5, 0.9, -0.4}};
  const ib::Vec3 a(0.5, -0.25, 1.0);
  fluid.set_initial_condition(
      [&](const fluid::Real3& x, double) {
        const ib::Vec3 v = a + B * ib::Vec3(x[0], x[1], x[2]);
        return fluid::Real3{v[0], v[1], v[2]};
      },
      nullptr, 0.0);
  const fe::Mesh mesh =
      fe::box_mesh(fe::CellShape::hexahedron, fe::Vec3(0.3, 0.35, 0.3), fe::Vec3(0.7, 0.65, 0.6), {5, 4, 4});
  fe::SolidModel solid(mesh, one_part(mesh, neo_hookean(100.0, 0.0)), 2, PETSC_COMM_WORLD);
  for (fe::MassKind kind : {fe::MassKind::consistent, fe::MassKind::lumped}) {
    ib::IbfeSettings s;
    s.velocity_projection = s.force_projection = kind;
    ib::IbfeIntegrator ibfe(fluid, solid, s);
    const std::vector<double> zero(solid.num_dofs(), 0.0);
    const std::vector<double> U = ibfe.nodal_velocity(fluid.state(), zero);
    double worst = 0.0;
    for (std::size_t n = 0; n < mesh.num_nodes(); ++n) {
      const ib::Vec3 exact = a + B * mesh.nodes()[n];
      const ib::Vec3 got(U[3 * n], U[3 * n + 1], U[3 * n + 2]);
      worst = std::max(worst, (got - exact).cwiseAbs().maxCoeff());
    }
    if (kind == fe::MassKind::consistent) {
      EXPECT_LT(worst, 1e-10) << "consistent";
    } else {
      // Lumped: U_a = int N_a u / int N_a is u at the N_a-weighted centroid of the node's support,
      // which lies within half an element (0.08 cm) of the node in each direction: at most
      // max_i sum_j |B_ij| h_e / 2 off, reached at boundary nodes; exact at interior nodes of a
      // uniform mesh (their supports are symmetric).
      const double bound = B.cwiseAbs().rowwise().sum().maxCoeff() * 0.5 * 0.08;
      EXPECT_GT(worst, 1e-3) << "lumped is not exact for linear fields";
      EXPECT_LT(worst, bound + 1e-12) << "lumped";
    }
  }
}
