// Nodal forces from the weak form: the patch test (a homogeneous deformation gives zero force at every
// interior node of a distorted mesh, and Newton reproduces it exactly from boundary data), forces that
// are minus the gradient of the energy, a stiffness that is the derivative of the forces, and
// identical results on 1 and 2 ranks. Each with the law fully integrated and with selective reduced
// integration (the volumetric term lambda/2 (ln J)^2 as a centre law, one point per element).
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <tuple>

#include <gtest/gtest.h>
#include <petscmat.h>

#include "fe/quasi_static.hpp"
#include "fe/solid.hpp"
#include "io/petsc_check.hpp"
#include "tests/fe/neo_hookean_fixture.hpp"

using namespace ibvalve::fe;
namespace petsc = ibvalve::petsc;

namespace {

constexpr double mu = 1.0e4, lambda = 4.0e4; // dyn/cm^2

Mesh distorted_box(CellShape shape, std::array<int, 3> n = {4, 3, 3})
{
  Mesh mesh = box_mesh(shape, Vec3(0, 0, 0), Vec3(1, 0.8, 0.6), n);
  perturb_interior_nodes(mesh, 0.2);
  return mesh;
}

enum class Integration { full, selective };

// The fixture's energy is linear in (mu, lambda): the selective split is the (mu, 0) part on the full
// rule plus the (0, lambda) part, lambda/2 (ln J)^2, at the element centre.
std::vector<BodyPart> one_part(const Mesh& mesh, Integration integration)
{
  BodyPart part{"body", mesh.group("body").elements, {}};
  if (integration == Integration::full) {
    part.laws.push_back(std::make_shared<fixtures::NeoHookeanFixture>(mu, lambda));
  } else {
    part.laws.push_back(std::make_shared<fixtures::NeoHookeanFixture>(mu, 0.0));
    part.centre_laws.push_back(std::make_shared<fixtures::NeoHookeanFixture>(0.0, lambda));
  }
  return {part};
}

// A homogeneous deformation x = A X + c with a finite stretch and shear.
Eigen::Matrix3d homogeneous_gradient()
{
  Eigen::Matrix3d F;
  F << 1.2, 0.1, -0.05, 0.05, 0.9, 0.08, -0.02, 0.03, 1.1;
  return F;
}

std::vector<double> homogeneous_displacement(const Mesh& mesh)
{
  const Eigen::Matrix3d H = homogeneous_gradient() - Eigen::Matrix3d::Identity();
  std::vector<double> u(3 * mesh.num_nodes());
  for (std::size_t n = 0; n < mesh.num_nodes(); ++n) {
    const Vec3 d = H * mesh.nodes()[n] + Vec3(0.01, -0.02, 0.03);
    for (int i = 0; i < 3; ++i) u[3 * n + i] = d[i];
  }
  return u;
}

std::vector<char> boundary_nodes(const Mesh& mesh)
{
  std::vector<char> on(mesh.num_nodes(), 0);
  for (const auto& face : mesh.boundary_faces())
    for (int n : face) on[n] = 1;
  return on;
}

} // namespace

class Assembly : public ::testing::TestWithParam<std::tuple<CellShape, Integration>> {
 protected:
  CellShape shape() const { return std::get<0>(GetParam()); }
  std::vector<BodyPart> parts(const Mesh& mesh) const { return one_part(mesh, std::get<1>(GetParam())); }
};

TEST_P(Assembly, PatchTestInteriorForcesVanishForAHomogeneousDeformation)
{
  const Mesh mesh = distorted_box(shape());
  const SolidModel solid(mesh, parts(mesh), 2, PETSC_COMM_WORLD);
  const std::vector<double> u = homogeneous_displacement(mesh);
  std::vector<double> f(u.size());
  solid.forces(u, f);
  const auto on_boundary = boundary_nodes(mesh);
  // Scale: the largest nodal force (a boundary node carries P N dA ~ mu h^2).
  double largest = 0, interior = 0;
  Vec3 total = Vec3::Zero();
  for (std::size_t n = 0; n < mesh.num_nodes(); ++n) {
    const Vec3 fn(f[3 * n], f[3 * n + 1], f[3 * n + 2]);
    largest = std::max(largest, fn.norm());
    total += fn;
    if (!on_boundary[n]) interior = std::max(interior, fn.norm());
  }
  EXPECT_GT(largest, 10.0);
  EXPECT_LT(interior / largest, 1e-12);
  EXPECT_LT(total.norm() / largest, 1e-12); // Newton's third law: the internal forces balance.
  // The boundary forces carry the nominal stress: since sum_a X_a (x) grad N_a = I exactly,
  // sum_a f_a (x) X_a = - P V (the virtual work of a homogeneous P).
  const fixtures::NeoHookeanFixture law(mu, lambda);
  const Eigen::Matrix3d P = law.stress(homogeneous_gradient(), {});
  Eigen::Matrix3d moment = Eigen::Matrix3d::Zero();
  for (std::size_t n = 0; n < mesh.num_nodes(); ++n)
    moment += Vec3(f[3 * n], f[3 * n + 1], f[3 * n + 2]) * mesh.nodes()[n].transpose();
  EXPECT_LT((moment + P * mesh.volume()).norm() / P.norm(), 1e-12);
}

TEST_P(Assembly, PatchTestNewtonReproducesTheHomogeneousDeformation)
{
  const Mesh mesh = distorted_box(shape());
  const SolidModel solid(mesh, parts(mesh), 2, PETSC_COMM_WORLD);
  const std::vector<double> exact = homogeneous_displacement(mesh);
  const auto on_boundary = boundary_nodes(mesh);
  DirichletCondition boundary;
  for (std::size_t n = 0; n < mesh.num_nodes(); ++n)
    if (on_boundary[n]) boundary.nodes.push_back(static_cast<int>(n));
  const Eigen::Matrix3d H = homogeneous_gradient() - Eigen::Matrix3d::Identity();
  boundary.displacement = [H](const Vec3& X) { return Vec3(H * X + Vec3(0.01, -0.02, 0.03)); };
  QuasiStaticOptions options;
  options.load_steps = 2;
  options.relative_tolerance = 1e-14; // converge to round-off: the exact answer is in the FE space
  options.absolute_tolerance = 1e-9;
  QuasiStaticSolver solver(solid, {boundary}, {}, options);
  const QuasiStaticResult result = solver.solve();
  double error = 0;
  for (std::size_t i = 0; i < exact.size(); ++i)
    error = std::max(error, std::abs(result.displacement[i] - exact[i]));
  EXPECT_LT(error, 1e-12);
  for (int iterations : result.newton_iterations) EXPECT_LE(iterations, 6);
}

TEST_P(Assembly, ForcesAreMinusTheEnergyGradientAndStiffnessTheirDerivative)
{
  const Mesh mesh = distorted_box(shape(), {2, 2, 2});
  const SolidModel solid(mesh, parts(mesh), 2, PETSC_COMM_WORLD);
  std::vector<double> u = homogeneous_displacement(mesh);
  std::mt19937 generator(3);
  std::uniform_real_distribution<double> noise(-0.02, 0.02);
  for (double& v : u) v += noise(generator);
  std::vector<double> f(u.size()), fp(u.size()), fm(u.size());
  solid.forces(u, f);

  NodalSystem system(mesh, 3, PETSC_COMM_WORLD);
  const petsc::OwnedMat K = system.create_matrix();
  solid.add_stiffness(u, system, K);
  PETSC_CHECK(MatAssemblyBegin(K, MAT_FINAL_ASSEMBLY));
  PETSC_CHECK(MatAssemblyEnd(K, MAT_FINAL_ASSEMBLY));
  const petsc::OwnedVec column = system.create_vector(), Kcol = system.create_vector();

  const double h = 1e-7;
  double force_error = 0, force_scale = 0, stiffness_error = 0, stiffness_scale = 0;
  for (std::size_t j = 0; j < u.size(); j += 5) {
    std::vector<double> up = u, um = u;
    up[j] += h;
    um[j] -= h;
    const double dW = (solid.energy(up) - solid.energy(um)) / (2 * h);
    force_error = std::max(force_error, std::abs(-dW - f[j]));
    force_scale = std::max(force_scale, std::abs(f[j]));
    solid.forces(up, fp);
    solid.forces(um, fm);
    std::vector<double> unit(u.size(), 0.0);
    unit[j] = 1.0;
    system.scatter(unit, column);
    PETSC_CHECK(MatMult(K, column, Kcol));
    const std::vector<double> k = system.gather(Kcol);
    for (std::size_t i = 0; i < u.size(); ++i) {
      const double fd = -(fp[i] - fm[i]) / (2 * h);
      stiffness_error = std::max(stiffness_error, std::abs(fd - k[i]));
      stiffness_scale = std::max(stiffness_scale, std::abs(k[i]));
    }
  }
  EXPECT_LT(force_error / force_scale, 1e-6);
  EXPECT_LT(stiffness_error / stiffness_scale, 1e-6);
  // The tangent of a hyperelastic law is symmetric (K = d^2 Energy / du^2).
  PetscBool symmetric = PETSC_FALSE;
  PETSC_CHECK(MatIsSymmetric(K, 1e-8 * stiffness_scale, &symmetric));
  EXPECT_TRUE(symmetric);
}

TEST_P(Assembly, AllRanksTogetherGiveTheOneRankForces)
{
  const Mesh mesh = distorted_box(shape());
  std::vector<double> u = homogeneous_displacement(mesh);
  std::mt19937 generator(11);
  std::uniform_real_distribution<double> noise(-0.02, 0.02);
  for (double& v : u) v += noise(generator);
  const SolidModel everyone(mesh, parts(mesh), 2, PETSC_COMM_WORLD);
  const SolidModel alone(mesh, parts(mesh), 2, PETSC_COMM_SELF);
  std::vector<double> f_all(u.size()), f_one(u.size());
  everyone.forces(u, f_all);
  alone.forces(u, f_one);
  double error = 0, scale = 0;
  for (std::size_t i = 0; i < u.size(); ++i) {
    error = std::max(error, std::abs(f_all[i] - f_one[i]));
    scale = std::max(scale, std::abs(f_one[i]));
  }
  EXPECT_LT(error / scale, 1e-13);
  EXPECT_NEAR(everyone.energy(u), alone.energy(u), 1e-13 * std::abs(alone.energy(u)));
}

INSTANTIATE_TEST_SUITE_P(HexAndTet, Assembly,
                         ::testing::Combine(::testing::Values(CellShape::hexahedron, CellShape::tetrahedron),
                                            ::testing::Values(Integration::full, Integration::selective)),
                         [](const auto& info) {
                           return std::string(std::get<0>(info.param) == CellShape::hexahedron ? "hex"
                                                                                               : "tet") +
                                  (std::get<1>(info.param) == Integration::full ? "Full" : "Selective");
                         });
