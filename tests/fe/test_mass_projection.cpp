// Mass matrices integrate the volume (and linear functions) exactly on distorted meshes; the
// consistent L2 projection reproduces linear fields exactly, the lumped one constants; on 2 ranks the
// results equal the 1-rank ones.
#include <cmath>

#include <gtest/gtest.h>
#include <petscmat.h>

#include "fe/mass.hpp"
#include "io/petsc_check.hpp"

using namespace ibvalve::fe;
namespace petsc = ibvalve::petsc;

namespace {

Mesh distorted_box(CellShape shape)
{
  Mesh mesh = box_mesh(shape, Vec3(0, 0, 0), Vec3(1.5, 1, 0.8), {5, 4, 3});
  perturb_interior_nodes(mesh, 0.2);
  return mesh;
}

} // namespace

class MassAndProjection : public ::testing::TestWithParam<CellShape> {};

TEST_P(MassAndProjection, MassMatricesIntegrateVolumeAndLinearFieldsExactly)
{
  const Mesh mesh = distorted_box(GetParam());
  const QuadratureData quadrature(mesh, 2);
  NodalSystem system(mesh, 1, PETSC_COMM_WORLD);
  const petsc::OwnedMat M = consistent_mass_matrix(mesh, quadrature, system);
  const petsc::OwnedVec ones = system.create_vector(), x = system.create_vector(),
                        Mx = system.create_vector();
  PETSC_CHECK(VecSet(ones, 1.0));
  std::vector<double> xs(mesh.num_nodes());
  for (std::size_t n = 0; n < mesh.num_nodes(); ++n) xs[n] = mesh.nodes()[n][0];
  system.scatter(xs, x);
  PETSC_CHECK(MatMult(M, x, Mx));
  PetscScalar volume = 0, moment = 0;
  PETSC_CHECK(VecDot(ones, Mx, &moment)); // 1^T M x = int x dX
  PETSC_CHECK(MatMult(M, ones, Mx));
  PETSC_CHECK(VecDot(ones, Mx, &volume)); // 1^T M 1 = volume
  const double exact_volume = 1.5 * 1 * 0.8;
  EXPECT_NEAR(volume, exact_volume, 1e-13);
  EXPECT_NEAR(moment, exact_volume * 0.75, 1e-13);
  const std::vector<double> lumped = lumped_mass(mesh, quadrature, PETSC_COMM_WORLD);
  double lumped_volume = 0;
  for (double m : lumped) {
    EXPECT_GT(m, 0.0);
    lumped_volume += m;
  }
  EXPECT_NEAR(lumped_volume, exact_volume, 1e-13);
}

TEST_P(MassAndProjection, ConsistentProjectionReproducesLinearFields)
{
  const Mesh mesh = distorted_box(GetParam());
  const QuadratureData quadrature(mesh, 2);
  const L2Projection projection(mesh, quadrature, MassKind::consistent, PETSC_COMM_WORLD);
  auto linear = [](const Vec3& X) { return 0.3 + 2.0 * X[0] - 1.5 * X[1] + 0.7 * X[2]; };
  const std::vector<double> nodal = projection.project(linear);
  double error = 0;
  for (std::size_t n = 0; n < mesh.num_nodes(); ++n)
    error = std::max(error, std::abs(nodal[n] - linear(mesh.nodes()[n])));
  EXPECT_LT(error, 1e-10);

  // Vector data at quadrature points (3 components).
  const int points = quadrature.points_per_element();
  std::vector<double> values(mesh.num_elements() * points * 3);
  for (std::size_t e = 0; e < mesh.num_elements(); ++e)
    for (int q = 0; q < points; ++q)
      for (int c = 0; c < 3; ++c) values[(e * points + q) * 3 + c] = (c + 1) * linear(quadrature.point(e, q));
  const std::vector<double> vector_nodal = projection.project(values, 3);
  error = 0;
  for (std::size_t n = 0; n < mesh.num_nodes(); ++n)
    for (int c = 0; c < 3; ++c)
      error = std::max(error, std::abs(vector_nodal[3 * n + c] - (c + 1) * linear(mesh.nodes()[n])));
  EXPECT_LT(error, 1e-10);
}

TEST_P(MassAndProjection, LumpedProjectionReproducesConstants)
{
  const Mesh mesh = distorted_box(GetParam());
  const QuadratureData quadrature(mesh, 2);
  const L2Projection projection(mesh, quadrature, MassKind::lumped, PETSC_COMM_WORLD);
  const std::vector<double> nodal = projection.project([](const Vec3&) { return 4.25; });
  for (double v : nodal) EXPECT_NEAR(v, 4.25, 1e-13);
}

INSTANTIATE_TEST_SUITE_P(HexAndTet, MassAndProjection,
                         ::testing::Values(CellShape::hexahedron, CellShape::tetrahedron));
