// Fiber fields from Laplace problems: exact on a slab (a linear potential is in the FE space),
// circumferential on an annular sector with FD2-type data (u = 0 and 1 on the two halves of the
// "attachment" boundary) with an error that falls under mesh refinement, symmetric FD1 fields, the
// same answers on 1 and 2 ranks, and a per-element fiber file that reads back exactly.
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <numbers>
#include <sstream>

#include <gtest/gtest.h>
#include <petscsys.h>

#include "base/errors.hpp"
#include "base/logger.hpp"
#include "fibers/rules.hpp"

using namespace ibvalve;
using namespace ibvalve::fibers;
using fe::CellShape;

namespace {

double angle_degrees(const Vec3& a, const Vec3& b)
{
  // Fibers are lines: the angle between the directions up to sign, in [0, 90] degrees.
  const double c = std::min(1.0, std::abs(a.normalized().dot(b.normalized())));
  return std::acos(c) * 180.0 / std::numbers::pi;
}

Vec3 centroid(const fe::Mesh& mesh, std::size_t e)
{
  Vec3 c = Vec3::Zero();
  for (int n : mesh.element(e)) c += mesh.nodes()[n];
  return c / static_cast<double>(mesh.nodes_per_element());
}

} // namespace

class Fibers : public ::testing::TestWithParam<CellShape> {};

TEST_P(Fibers, SlabWithDirichletFacesGivesAUniformField)
{
  fe::Mesh mesh = fe::box_mesh(GetParam(), Vec3(0, 0, 0), Vec3(2, 1, 0.3), {6, 4, 2});
  fe::perturb_interior_nodes(mesh, 0.2);
  LeafletSpec spec;
  spec.tau1 = "xmin";
  spec.tau2 = "xmax";
  const FiberField field = compute_fibers(mesh, FiberRule::FD2, {spec}, PETSC_COMM_WORLD);
  double worst = 0;
  for (const Vec3& f : field.element_directions) worst = std::max(worst, angle_degrees(f, Vec3::UnitX()));
  EXPECT_LT(worst * std::numbers::pi / 180, 1e-10);
  for (std::size_t n = 0; n < mesh.num_nodes(); ++n)
    EXPECT_NEAR(field.potential[n], mesh.nodes()[n][0] / 2, 1e-10);
}

TEST_P(Fibers, AnnularSectorWithFd2DataIsCircumferentialAndConverges)
{
  // The attachment boundary is both end faces (theta = 0 and theta = 90 degrees); the split by the
  // plane through the z axis and the sector's centroid gives tau1 and tau2. The exact potential is
  // theta / (pi/2), whose gradient is the circumferential direction e_theta.
  std::vector<double> errors;
  for (int refinement : {2, 4, 8}) {
    fe::Mesh mesh = fe::annular_sector_mesh(GetParam(), 1.0, 1.3, std::numbers::pi / 2, 0.2,
                                            {2 * refinement, 6 * refinement, 1});
    fe::PhysicalGroup attachment = mesh.group("theta0");
    attachment.name = "attachment";
    const auto& other = mesh.group("theta1").cells;
    attachment.cells.insert(attachment.cells.end(), other.begin(), other.end());
    attachment.tag = -1;
    mesh.add_group(attachment);
    mesh.add_volume_group("leaflet", mesh.group("body").elements);
    LeafletSpec spec;
    spec.group = "leaflet";
    const FiberField field = compute_fibers(mesh, FiberRule::FD2, {spec}, PETSC_COMM_WORLD);
    // Per element (the file a run reads) and per quadrature point (grad u / |grad u| there).
    double worst = 0, worst_element = 0;
    for (std::size_t e = 0; e < mesh.num_elements(); ++e) {
      const Vec3 c = centroid(mesh, e);
      worst_element =
          std::max(worst_element, angle_degrees(field.element_directions[e], Vec3(-c[1], c[0], 0)));
    }
    const fe::QuadratureData quadrature(mesh, 2);
    const std::vector<Vec3> at_points = directions_at_points(mesh, quadrature, field.potential);
    for (std::size_t e = 0; e < mesh.num_elements(); ++e)
      for (int q = 0; q < quadrature.points_per_element(); ++q) {
        const Vec3& X = quadrature.point(e, q);
        worst = std::max(
            worst, angle_degrees(at_points[e * quadrature.points_per_element() + q], Vec3(-X[1], X[0], 0)));
      }
    EXPECT_LE(worst_element, worst + 1e-9);
    std::ostringstream message;
    message << "annular sector, " << mesh.num_elements() << " elements: max angle error " << worst
            << " degrees at quadrature points, " << worst_element << " per element";
    base::Logger::global().info(message.str());
    errors.push_back(worst);
  }
  EXPECT_LT(errors.back(), 2.0);
  if (GetParam() == CellShape::hexahedron) {
    // On this mesh the trilinear iso-surfaces of the potential are planes through the axis (a
    // constant-eta line of a cell joins points on the same ray), so the field is circumferential to
    // solver tolerance on every mesh: nothing left to converge.
    for (double error : errors) EXPECT_LT(error, 1e-4);
  } else {
    // Linear tetrahedra: first order, the error halves with h.
    for (std::size_t i = 1; i < errors.size(); ++i) EXPECT_NEAR(errors[i - 1] / errors[i], 2.0, 0.2);
  }
}

TEST_P(Fibers, Fd1FieldIsMirrorSymmetricBetweenItsCornerPoints)
{
  // A leaflet-like plate with n1 and n2 at the two ends of its "free edge" (y = 1): the potential
  // obeys u(L - x) = 1 - u(x), so the fibers of mirrored elements are mirrored.
  const fe::Mesh mesh = fe::box_mesh(GetParam(), Vec3(0, 0, 0), Vec3(2, 1, 0.1), {8, 4, 1});
  LeafletSpec spec;
  spec.n1 = "point:0,1,0";
  spec.n2 = "point:2,1,0";
  const FiberField field = compute_fibers(mesh, FiberRule::FD1, {spec}, PETSC_COMM_WORLD);
  // (Kuhn's tetrahedra are not mirror symmetric; the hexahedral mesh is.)
  if (GetParam() == CellShape::hexahedron) {
    for (std::size_t n = 0; n < mesh.num_nodes(); ++n) {
      const Vec3& X = mesh.nodes()[n];
      const int mirror = nearest_node(mesh, Vec3(2 - X[0], X[1], X[2]));
      EXPECT_NEAR(field.potential[n], 1 - field.potential[mirror], 1e-8);
    }
  }
  EXPECT_NEAR(field.potential[nearest_node(mesh, Vec3(0, 1, 0))], 1.0, 1e-12);
  EXPECT_NEAR(field.potential[nearest_node(mesh, Vec3(2, 1, 0))], 0.0, 1e-12);
  // Near the free edge's middle the fibers run along it (x).
  for (std::size_t e = 0; e < mesh.num_elements(); ++e) {
    const Vec3 c = centroid(mesh, e);
    if (std::abs(c[0] - 1) < 0.2 && c[1] > 0.7) {
      EXPECT_LT(angle_degrees(field.element_directions[e], Vec3::UnitX()), 5.0);
    }
  }
}

TEST_P(Fibers, AllRanksGiveTheOneRankPotential)
{
  const fe::Mesh mesh = fe::annular_sector_mesh(GetParam(), 1.0, 1.3, std::numbers::pi / 2, 0.2, {3, 9, 2});
  const std::vector<DirichletSet> conditions{{mesh.group("theta0").nodes, 0.0},
                                             {mesh.group("theta1").nodes, 1.0}};
  const std::vector<double> together = solve_laplace(mesh, conditions, PETSC_COMM_WORLD);
  const std::vector<double> alone = solve_laplace(mesh, conditions, PETSC_COMM_SELF);
  for (std::size_t n = 0; n < mesh.num_nodes(); ++n) EXPECT_NEAR(together[n], alone[n], 1e-9);
}

INSTANTIATE_TEST_SUITE_P(HexAndTet, Fibers, ::testing::Values(CellShape::hexahedron, CellShape::tetrahedron));

TEST(FiberSelectors, BadSelectorsAreInputErrors)
{
  const fe::Mesh mesh = fe::box_mesh(CellShape::hexahedron, Vec3(0, 0, 0), Vec3(1, 1, 1), {2, 2, 2});
  EXPECT_THROW(select_nodes(mesh, "no_such_group"), InputError);
  EXPECT_THROW(select_nodes(mesh, "point:1,2"), InputError);
  EXPECT_THROW(select_nodes(mesh, "plane:0,0,0,0,0,0"), InputError);
  EXPECT_THROW(select_nodes(mesh, "plane:5,0,0,1,0,0"), InputError); // no node there
  EXPECT_EQ(select_nodes(mesh, "plane:0,0,0,1,0,0").size(), 9u);
  EXPECT_THROW(parse_fiber_rule("FD3"), InputError);
  EXPECT_EQ(parse_fiber_rule("fd2"), FiberRule::FD2);
  LeafletSpec spec; // no n1/n2 anywhere
  EXPECT_THROW(compute_fibers(mesh, FiberRule::FD1, {spec}, PETSC_COMM_WORLD), InputError);
}

TEST(FiberFile, RoundTripAndBadFiles)
{
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  const std::filesystem::path path = fmt::format("fibers_{}.txt", rank);
  const std::vector<Vec3> directions{Vec3(1, 0, 0), Vec3(0.6, 0.8, 0), Vec3(1.0 / 3, 2.0 / 3, 2.0 / 3)};
  write_element_fibers(path, directions, PETSC_COMM_SELF);
  const std::vector<Vec3> back = read_element_fibers(path, 3);
  for (std::size_t e = 0; e < directions.size(); ++e) EXPECT_EQ(back[e], directions[e]);
  EXPECT_THROW(read_element_fibers(path, 4), InputError);
  std::ofstream(path) << "ibvalve-element-fibers 1 2\n1 0 0\n";
  EXPECT_THROW(read_element_fibers(path), InputError);
  std::ofstream(path) << "something else\n";
  EXPECT_THROW(read_element_fibers(path), InputError);
  std::filesystem::remove(path);
}
