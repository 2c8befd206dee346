// The quasi-static solver against known solutions:
//  - uniaxial tension of a compressible neo-Hookean bar under a dead end load: the FE stretches equal
//    the analytic ones (P11 = T, P22 = P33 = 0 solved exactly), since the answer is homogeneous;
//  - a manufactured bending solution (Euler–Bernoulli kinematics u_z = a sin(k x), u_x = -a k z' cos(k x),
//    body force b = -Div P(F(u)) computed from the law's tangent): the displacement error falls as h^2
//    in L2 on three meshes (trilinear and linear elements).
#include <cmath>
#include <memory>
#include <numbers>
#include <sstream>

#include <gtest/gtest.h>

#include "base/errors.hpp"
#include "base/logger.hpp"
#include "fe/loads.hpp"
#include "fe/quasi_static.hpp"
#include "tests/fe/neo_hookean_fixture.hpp"

using namespace ibvalve::fe;
using ibvalve::fe::fixtures::NeoHookeanFixture;

namespace {

constexpr double mu = 1.0e4, lambda = 4.0e4;

std::vector<BodyPart> one_part(const Mesh& mesh)
{
  return {BodyPart{"body", mesh.group("body").elements, {std::make_shared<NeoHookeanFixture>(mu, lambda)}}};
}

// Stretches (axial l, lateral t) with P11(l, t) = T and P22 = P33 = 0 for F = diag(l, t, t):
// P11 = mu (l - 1/l) + lambda ln(l t^2) / l, P22 = mu (t - 1/t) + lambda ln(l t^2) / t. Newton in 2-D.
std::pair<double, double> uniaxial_stretches(double T)
{
  double l = 1, t = 1;
  for (int iteration = 0; iteration < 50; ++iteration) {
    const double logJ = std::log(l * t * t);
    const Eigen::Vector2d r(mu * (l - 1 / l) + lambda * logJ / l - T, mu * (t - 1 / t) + lambda * logJ / t);
    Eigen::Matrix2d J;
    J << mu * (1 + 1 / (l * l)) + lambda * (1 - logJ) / (l * l), 2 * lambda / (l * t), lambda / (l * t),
        mu * (1 + 1 / (t * t)) + lambda * (2 - logJ) / (t * t);
    const Eigen::Vector2d step = J.lu().solve(r);
    l -= step[0];
    t -= step[1];
    if (step.norm() < 1e-15) break;
  }
  return {l, t};
}

} // namespace

class SolidVerification : public ::testing::TestWithParam<CellShape> {};

TEST_P(SolidVerification, UniaxialTensionOfANeoHookeanBarGivesTheAnalyticStretch)
{
  const double length = 3.0, T = 0.6 * mu;
  Mesh mesh = box_mesh(GetParam(), Vec3(0, 0, 0), Vec3(length, 1, 1), {6, 2, 2});
  const SolidModel solid(mesh, one_part(mesh), 2, PETSC_COMM_WORLD);
  // Symmetry planes hold the bar (rollers), the x = L end carries the dead traction T e_x.
  std::vector<DirichletCondition> rollers{dirichlet_on_group(mesh, "xmin", {true, false, false}),
                                          dirichlet_on_group(mesh, "ymin", {false, true, false}),
                                          dirichlet_on_group(mesh, "zmin", {false, false, true})};
  const std::vector<double> load = surface_traction_load(
      mesh, "xmax", [&](const Vec3&) { return Vec3(T, 0, 0); }, 2, PETSC_COMM_WORLD);
  QuasiStaticOptions options;
  options.load_steps = 3;
  options.relative_tolerance = 1e-13;
  options.absolute_tolerance = 1e-8;
  QuasiStaticSolver solver(solid, rollers, load, options);
  const QuasiStaticResult result = solver.solve();
  const auto [l, t] = uniaxial_stretches(T);
  ASSERT_GT(l, 1.2); // a finite stretch, not a linear-elastic one
  double error = 0;
  for (std::size_t n = 0; n < mesh.num_nodes(); ++n) {
    const Vec3& X = mesh.nodes()[n];
    const Vec3 exact((l - 1) * X[0], (t - 1) * X[1], (t - 1) * X[2]);
    error = std::max(error, (Vec3(result.displacement[3 * n], result.displacement[3 * n + 1],
                                  result.displacement[3 * n + 2]) -
                             exact)
                                .norm());
  }
  EXPECT_LT(error / ((l - 1) * length), 1e-10);
  std::ostringstream message;
  message << "uniaxial: stretch " << l << ", lateral " << t << ", max nodal error " << error << " cm";
  ibvalve::base::Logger::global().info(message.str());
}

TEST(SolidFailures, NewtonThatCannotConvergeIsARunErrorNamingTheStep)
{
  const Mesh mesh = box_mesh(CellShape::hexahedron, Vec3(0, 0, 0), Vec3(3, 1, 1), {3, 1, 1});
  const SolidModel solid(mesh, one_part(mesh), 2, PETSC_COMM_WORLD);
  const std::vector<double> load = surface_traction_load(
      mesh, "xmax", [](const Vec3&) { return Vec3(2 * mu, 0, 0); }, 2, PETSC_COMM_WORLD);
  QuasiStaticOptions options;
  options.max_iterations = 1; // one Newton step cannot reach 1e-10 from a large load
  QuasiStaticSolver solver(solid, {dirichlet_on_group(mesh, "xmin")}, load, options);
  try {
    solver.solve();
    FAIL() << "expected a RunError";
  } catch (const ibvalve::RunError& error) {
    EXPECT_NE(std::string(error.what()).find("load step 1 of 1"), std::string::npos) << error.what();
  }
}

TEST(SolidFailures, InvertedElementIsAnInputError)
{
  Mesh mesh = box_mesh(CellShape::tetrahedron, Vec3(0, 0, 0), Vec3(1, 1, 1), {1, 1, 1});
  // Push the far corner through the opposite faces: some tetrahedra turn inside out.
  mesh.nodes()[mesh.group("corner_hi").nodes[0]] = Vec3(-1, -1, -1);
  EXPECT_THROW(QuadratureData(mesh, 2), ibvalve::InputError);
}

namespace {

// Manufactured bending: u_z = a sin(k x), u_x = -a k (z - zc) cos(k x), u_y = 0 (cross-sections stay
// normal to the bent axis). Returns u, grad u (H(i, j) = du_i/dX_j) and second derivatives.
struct Bending {
  double a, k, zc;
  Vec3 u(const Vec3& X) const
  {
    return Vec3(-a * k * (X[2] - zc) * std::cos(k * X[0]), 0.0, a * std::sin(k * X[0]));
  }
  Eigen::Matrix3d gradient(const Vec3& X) const
  {
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    H(0, 0) = a * k * k * (X[2] - zc) * std::sin(k * X[0]);
    H(0, 2) = -a * k * std::cos(k * X[0]);
    H(2, 0) = a * k * std::cos(k * X[0]);
    return H;
  }
  // d2u_i / dX_j dX_l as hessian[i](j, l).
  std::array<Eigen::Matrix3d, 3> hessian(const Vec3& X) const
  {
    std::array<Eigen::Matrix3d, 3> h{Eigen::Matrix3d::Zero(), Eigen::Matrix3d::Zero(),
                                     Eigen::Matrix3d::Zero()};
    h[0](0, 0) = a * k * k * k * (X[2] - zc) * std::cos(k * X[0]);
    h[0](0, 2) = h[0](2, 0) = a * k * k * std::sin(k * X[0]);
    h[2](0, 0) = -a * k * k * std::sin(k * X[0]);
    return h;
  }
};

// b = -Div P: (Div P)_i = dP_ij/dX_j = sum_kl T(i + 3j, k + 3l) d2u_k / dX_l dX_j.
Vec3 manufactured_body_force(const NeoHookeanFixture& law, const Bending& bending, const Vec3& X)
{
  const Eigen::Matrix3d F = Eigen::Matrix3d::Identity() + bending.gradient(X);
  const auto T = law.tangent(F, {});
  const auto h = bending.hessian(X);
  Vec3 div = Vec3::Zero();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l) div[i] += T(i + 3 * j, k + 3 * l) * h[k](l, j);
  return -div;
}

// L2 norm of u_h - u over the mesh with a degree-4 rule.
double l2_error(const Mesh& mesh, const std::vector<double>& uh, const Bending& bending)
{
  const QuadratureData fine(mesh, 4);
  double sum = 0;
  for (std::size_t e = 0; e < mesh.num_elements(); ++e) {
    const auto element = mesh.element(e);
    for (int q = 0; q < fine.points_per_element(); ++q) {
      Vec3 value = Vec3::Zero();
      for (std::size_t a = 0; a < element.size(); ++a)
        value += fine.value(q, static_cast<int>(a)) *
                 Vec3(uh[3 * element[a]], uh[3 * element[a] + 1], uh[3 * element[a] + 2]);
      sum += (value - bending.u(fine.point(e, q))).squaredNorm() * fine.JxW(e, q);
    }
  }
  return std::sqrt(sum);
}

} // namespace

TEST_P(SolidVerification, ManufacturedBendingConvergesAtSecondOrder)
{
  const double length = 2.0, depth = 0.5;
  const Bending bending{0.08, std::numbers::pi / length, 0.5 * depth};
  const NeoHookeanFixture law(mu, lambda);
  std::vector<double> errors;
  for (int refinement : {1, 2, 4}) {
    const Mesh mesh = box_mesh(GetParam(), Vec3(0, 0, 0), Vec3(length, depth, depth),
                               {8 * refinement, 2 * refinement, 2 * refinement});
    const SolidModel solid(mesh, one_part(mesh), 2, PETSC_COMM_WORLD);
    DirichletCondition boundary;
    std::vector<char> on(mesh.num_nodes(), 0);
    for (const auto& face : mesh.boundary_faces())
      for (int n : face) on[n] = 1;
    for (std::size_t n = 0; n < mesh.num_nodes(); ++n)
      if (on[n]) boundary.nodes.push_back(static_cast<int>(n));
    boundary.displacement = [&](const Vec3& X) { return bending.u(X); };
    const std::vector<double> load = body_force_load(
        mesh, solid.quadrature(), [&](const Vec3& X) { return manufactured_body_force(law, bending, X); },
        PETSC_COMM_WORLD);
    QuasiStaticOptions options;
    options.load_steps = 1;
    options.relative_tolerance = 1e-12;
    QuasiStaticSolver solver(solid, {boundary}, load, options);
    const QuasiStaticResult result = solver.solve();
    errors.push_back(l2_error(mesh, result.displacement, bending));
  }
  for (std::size_t i = 1; i < errors.size(); ++i) {
    const double order = std::log2(errors[i - 1] / errors[i]);
    std::ostringstream message;
    message << "bending: L2 errors " << errors[i - 1] << " -> " << errors[i] << ", observed order " << order;
    ibvalve::base::Logger::global().info(message.str());
    EXPECT_GT(order, 1.8);
    EXPECT_LT(order, 2.3);
  }
}

INSTANTIATE_TEST_SUITE_P(HexAndTet, SolidVerification,
                         ::testing::Values(CellShape::hexahedron, CellShape::tetrahedron));
