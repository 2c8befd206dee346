// Selective reduced integration (SRI) of a volumetric energy (fe/solid.hpp, BodyPart::centre_laws):
//  - the one "point" per element is the one-point Gauss rule at the centre on parallelepipeds, and the
//    exact element means on distorted hexes;
//  - it is exact for homogeneous deformations (energy = W(F) x volume on a distorted mesh); the patch
//    test on forces, Newton, forces = -grad energy and stiffness = d forces / du are in test_assembly.cpp;
//  - a nearly incompressible cantilever (kappa/mu = 1000) with ONE trilinear hex through the thickness:
//    fully integrated it locks (tip deflection a fraction of a percent of beam theory); with SRI it
//    converges, as the mesh is refined along the length, to the beam that one linear element through
//    the thickness can represent, and with 2 and 4 elements through the thickness to the continuum beam.
//
// The beam, in plane strain (u_y = 0 everywhere; one element across the width W), length L along x,
// height H along z, clamped at x = 0 (every node of the end fixed), a tip shear load P split evenly over
// the nodes of x = L, solved with linear elasticity (the stiffness at u = 0). The fixture's neo-Hookean
// law linearises to W = mu eps:eps + lambda/2 (tr eps)^2.
//
// Beam theory (Timoshenko): tip deflection d = P L^3 / (3 E I) + P L / (k G A), I = W H^3 / 12,
// A = W H, G = mu. The bending modulus E is the one of pure bending eps_xx = -kappa z:
//  - continuum, plane strain: eps_zz(z) free, eps_yy = 0: E' = 4 mu (lambda + mu) / (lambda + 2 mu)
//    (= E / (1 - nu^2); -> 4 mu as lambda / mu -> infinity, the incompressible plate modulus), k = 5/6;
//  - n trilinear elements through the thickness: eps_zz is constant in z within each element (u_z is
//    linear in z), so the thickness strain can only follow -eps_xx piecewise. With SRI the penalty sees
//    the element mean of tr eps only; minimising mu (eps_xx^2 + e^2) + lambda/2 (e - kappa z_k)^2 over
//    each element's e = eps_zz (z_k its mid-height) gives, integrated over the height,
//      E_n = 2 mu + 2 mu lambda / (lambda + 2 mu) (1 - 1/n^2)     (E_1 = 2 mu, E_n -> E' as n grows).
//    With one element the shear strain is constant through the thickness: k = 1.
//  - fully integrated: the 2-point Gauss rule in z also sees the part of tr eps linear in z within each
//    element, so the penalty acts on the bending strain itself:
//      E_full,n = E_n + lambda / n^2     (E_full,1 = lambda + 2 mu, about 250 x E' here): volumetric locking.
//  - the trilinear element adds its parasitic shear in bending: an element of length a H/n in pure
//    bending u_x = -kappa x z has the shear strain eps_xz = -kappa x / 2 too, which adds
//    mu kappa^2 a^2 H^3/(24 n^2) to the bending energy: E -> E + mu (element length / H)^2, i.e. the
//    one-element SRI beam is stiffer by the factor 1 + a^2/2 (second order in the element length).
#include <cmath>
#include <iomanip>
#include <memory>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>

#include <petscksp.h>

#include "base/logger.hpp"
#include "fe/solid.hpp"
#include "io/petsc_check.hpp"
#include "tests/fe/neo_hookean_fixture.hpp"

using namespace ibvalve::fe;
namespace petsc = ibvalve::petsc;
using ibvalve::fe::fixtures::NeoHookeanFixture;

namespace {

constexpr double mu = 1.0e4;                // dyn/cm^2
constexpr double lambda = 1000.0 * mu;      // nearly incompressible: nu = 0.4995
constexpr double L = 2.0, H = 0.1, W = 0.1; // cm; L / H = 20

enum class Integration { full, selective };

std::vector<BodyPart> neo_hookean_part(const Mesh& mesh, Integration integration)
{
  BodyPart part{"body", mesh.group("body").elements, {}};
  if (integration == Integration::full) {
    part.laws.push_back(std::make_shared<NeoHookeanFixture>(mu, lambda));
  } else {
    part.laws.push_back(std::make_shared<NeoHookeanFixture>(mu, 0.0));
    part.centre_laws.push_back(std::make_shared<NeoHookeanFixture>(0.0, lambda));
  }
  return {part};
}

double timoshenko_deflection(double P, double E, double k)
{
  const double I = W * H * H * H / 12.0, A = W * H;
  return P * L * L * L / (3.0 * E * I) + P * L / (k * mu * A);
}

double continuum_modulus()
{
  return 4.0 * mu * (lambda + mu) / (lambda + 2.0 * mu);
}

double layered_modulus(int layers)
{
  return 2.0 * mu + 2.0 * mu * lambda / (lambda + 2.0 * mu) * (1.0 - 1.0 / (layers * layers));
}

double locked_modulus(int layers)
{
  return layered_modulus(layers) + lambda / (layers * layers);
}

/// The modulus with the parasitic shear of elements of length L / along.
double with_parasitic_shear(double modulus, int along)
{
  const double length = L / along;
  return modulus + mu * (length / H) * (length / H);
}

constexpr double tip_load = 1.0; // dyn (linear elasticity: the ratios do not depend on it)

// Mean z-displacement of the tip nodes of the clamped plane-strain cantilever: linear elasticity,
// K(u = 0) u = f with K from SolidModel::add_stiffness (the exact derivative of the forces; a
// Newton solve of the hyperelastic problem would mix in lambda (ln J)^2 ~ lambda theta^4 from the
// rotations theta, large next to the bending stress when lambda / mu = 1000).
double tip_deflection(int elements_along, int elements_through, Integration integration)
{
  const Mesh mesh =
      box_mesh(CellShape::hexahedron, Vec3(0, 0, 0), Vec3(L, W, H), {elements_along, 1, elements_through});
  const SolidModel solid(mesh, neo_hookean_part(mesh, integration), 2, PETSC_COMM_WORLD);
  std::vector<PetscInt> fixed;
  std::vector<int> tip;
  for (std::size_t n = 0; n < mesh.num_nodes(); ++n) {
    const Vec3& X = mesh.nodes()[n];
    const auto dof = [n](int i) { return static_cast<PetscInt>(3 * n + i); };
    fixed.push_back(dof(1)); // plane strain
    if (X.x() < 1e-12 * L) {
      fixed.push_back(dof(0)); // clamped
      fixed.push_back(dof(2));
    }
    if (X.x() > (1 - 1e-12) * L) tip.push_back(static_cast<int>(n));
  }
  std::vector<double> load(3 * mesh.num_nodes(), 0.0);
  for (int n : tip) load[3 * n + 2] = tip_load / static_cast<double>(tip.size());

  NodalSystem system(mesh, 3, PETSC_COMM_WORLD);
  const petsc::OwnedMat K = system.create_matrix();
  const std::vector<double> zero(load.size(), 0.0);
  solid.add_stiffness(zero, system, K);
  PETSC_CHECK(MatAssemblyBegin(K, MAT_FINAL_ASSEMBLY));
  PETSC_CHECK(MatAssemblyEnd(K, MAT_FINAL_ASSEMBLY));
  const petsc::OwnedVec f = system.create_vector(), u = system.create_vector();
  system.scatter(load, f);
  zero_rows_columns(K, fixed, 1.0, u, f); // u = 0 there
  petsc::OwnedKSP ksp;
  PC pc;
  PETSC_CHECK(KSPCreate(PETSC_COMM_WORLD, ksp.out()));
  PETSC_CHECK(KSPSetOperators(ksp, K, K));
  PETSC_CHECK(KSPSetType(ksp, KSPPREONLY));
  PETSC_CHECK(KSPGetPC(ksp, &pc));
  PETSC_CHECK(PCSetType(pc, PCCHOLESKY)); // K is symmetric positive definite
  PETSC_CHECK(KSPSolve(ksp, f, u));
  const std::vector<double> displacement = system.gather(u);
  double deflection = 0;
  for (int n : tip) deflection += displacement[3 * n + 2];
  return deflection / static_cast<double>(tip.size());
}

Mesh sheared_box()
{
  Mesh mesh = box_mesh(CellShape::hexahedron, Vec3(0, 0, 0), Vec3(1, 0.8, 0.6), {3, 2, 2});
  Eigen::Matrix3d A;
  A << 1.0, 0.3, -0.2, 0.1, 0.9, 0.25, 0.05, -0.15, 1.1;
  for (Vec3& X : mesh.nodes()) X = A * X + Vec3(0.2, -0.1, 0.3);
  return mesh;
}

} // namespace

TEST(SelectiveIntegration, TheElementMeanIsTheCentreGaussPointOnParallelepipeds)
{
  const Mesh mesh = sheared_box(); // every element an (affinely mapped) parallelepiped
  const QuadratureData centre(mesh, 1);
  const QuadratureData means = QuadratureData::element_means(QuadratureData(mesh, 2));
  ASSERT_EQ(centre.points_per_element(), 1);
  ASSERT_EQ(means.points_per_element(), 1);
  double error = 0, scale = 0;
  for (std::size_t e = 0; e < mesh.num_elements(); ++e) {
    EXPECT_NEAR(means.JxW(e, 0), centre.JxW(e, 0), 1e-14);
    EXPECT_LT((means.point(e, 0) - centre.point(e, 0)).norm(), 1e-14);
    for (int a = 0; a < mesh.nodes_per_element(); ++a) {
      error = std::max(error, (means.gradient(e, 0, a) - centre.gradient(e, 0, a)).norm());
      scale = std::max(scale, centre.gradient(e, 0, a).norm());
    }
  }
  EXPECT_LT(error / scale, 1e-13);
}

TEST(SelectiveIntegration, HomogeneousDeformationEnergyIsWTimesVolumeOnADistortedMesh)
{
  for (CellShape shape : {CellShape::hexahedron, CellShape::tetrahedron}) {
    Mesh mesh = box_mesh(shape, Vec3(0, 0, 0), Vec3(1, 0.8, 0.6), {4, 3, 3});
    perturb_interior_nodes(mesh, 0.2);
    const SolidModel solid(mesh, neo_hookean_part(mesh, Integration::selective), 2, PETSC_COMM_WORLD);
    Eigen::Matrix3d F;
    F << 1.2, 0.1, -0.05, 0.05, 0.9, 0.08, -0.02, 0.03, 1.1;
    std::vector<double> u(3 * mesh.num_nodes());
    for (std::size_t n = 0; n < mesh.num_nodes(); ++n) {
      const Vec3 d = (F - Eigen::Matrix3d::Identity()) * mesh.nodes()[n];
      for (int i = 0; i < 3; ++i) u[3 * n + i] = d[i];
    }
    const double expected = NeoHookeanFixture(mu, lambda).energy(F, {}) * mesh.volume();
    EXPECT_NEAR(solid.energy(u), expected, 1e-12 * expected) << mesh.type().name();
  }
}

TEST(SelectiveIntegration, FiberStressOfTheFieldsIncludesTheCentreLaws)
{
  // A homogeneous F: the fields' f . sigma f with the law split over the two rules equals the one of
  // the whole law, at every point and in the element averages; fibers per point see the same.
  Mesh mesh = box_mesh(CellShape::hexahedron, Vec3(0, 0, 0), Vec3(1, 0.8, 0.6), {2, 2, 2});
  perturb_interior_nodes(mesh, 0.2);
  Eigen::Matrix3d F;
  F << 1.1, 0.05, 0.0, -0.03, 0.95, 0.02, 0.01, 0.0, 0.97;
  std::vector<double> u(3 * mesh.num_nodes());
  for (std::size_t n = 0; n < mesh.num_nodes(); ++n) {
    const Vec3 d = (F - Eigen::Matrix3d::Identity()) * mesh.nodes()[n];
    for (int i = 0; i < 3; ++i) u[3 * n + i] = d[i];
  }
  ibvalve::materials::FiberFrame frame;
  frame.f0 = Vec3(1, 1, 0).normalized();
  const Eigen::Matrix3d sigma = NeoHookeanFixture(mu, lambda).stress(F, {}) * F.transpose() / F.determinant();
  const Vec3 f = (F * frame.f0).normalized();
  const double expected = f.dot(sigma * f);
  SolidModel per_point(mesh, neo_hookean_part(mesh, Integration::selective), 2, PETSC_COMM_WORLD);
  per_point.set_fibers(std::vector<ibvalve::materials::FiberFrame>(
      mesh.num_elements() * per_point.quadrature().points_per_element(), frame));
  SolidModel per_element(mesh, neo_hookean_part(mesh, Integration::selective), 2, PETSC_COMM_WORLD);
  per_element.set_fibers(std::vector<ibvalve::materials::FiberFrame>(mesh.num_elements(), frame));
  for (const SolidModel* model : {&per_point, &per_element}) {
    for (double value : model->element_fields(u).fiber_stress) EXPECT_NEAR(value, expected, 1e-12 * mu);
    for (double value : model->point_fields(u).fiber_stress) EXPECT_NEAR(value, expected, 1e-12 * mu);
    EXPECT_LT((model->centre_fibers(0).f0 - frame.f0).norm(), 1e-15);
  }
}

TEST(SelectiveIntegration, OneElementThickCantileverLocksWhenFullyIntegratedAndConvergesWithSRI)
{
  const double continuum = timoshenko_deflection(tip_load, continuum_modulus(), 5.0 / 6.0);
  const double one_element_beam = timoshenko_deflection(tip_load, layered_modulus(1), 1.0);
  const double locked_beam = timoshenko_deflection(tip_load, locked_modulus(1), 1.0);
  std::ostringstream table;
  table << std::setprecision(4)
        << "plane-strain cantilever L/H = 20, lambda/mu = 1000, one hex through the thickness:\n"
        << "  continuum Timoshenko (E' = " << continuum_modulus() / mu << " mu, k = 5/6) d = " << continuum
        << " cm; one-element beam (E_1 = 2 mu, k = 1) d = " << one_element_beam
        << " cm; locked beam (E = lambda + 2 mu) d = " << locked_beam << " cm\n"
        << "  along | length/H | full/continuum | SRI/continuum | SRI/one-element beam - 1 | order | "
           "parasitic-shear prediction 1/(1 + a^2/2) - 1\n";
  std::vector<double> errors;
  for (int along : {20, 40, 80, 160}) {
    const double a = L / along / H;
    const double full = tip_deflection(along, 1, Integration::full);
    const double sri = tip_deflection(along, 1, Integration::selective);
    const double parasitic = 1.0 / (1.0 + 0.5 * a * a);
    errors.push_back(std::abs(sri / one_element_beam - 1.0));
    table << "  " << std::setw(5) << along << " | " << std::setw(8) << a << " | " << std::setw(14)
          << full / continuum << " | " << std::setw(13) << sri / continuum << " | " << std::setw(24)
          << sri / one_element_beam - 1.0 << " | ";
    if (errors.size() > 1)
      table << std::setw(5) << std::log2(errors[errors.size() - 2] / errors.back());
    else
      table << "     ";
    table << " | " << parasitic - 1.0 << "\n";
    // Locked: the constrained modulus lambda + 2 mu carries the bending (0.6 % of the continuum's
    // deflection, the shear compliance making up a third of it).
    EXPECT_NEAR(full / locked_beam, 1.0, 0.02) << along << " elements along";
    EXPECT_LT(full / continuum, 0.01);
    // SRI: the one-element beam up to the element's parasitic shear, which the formula predicts.
    EXPECT_NEAR(sri / one_element_beam, parasitic, 0.003) << along << " elements along";
  }
  // Second order along the length; within a few percent once the elements are a quarter of the
  // thickness long, and within 1 % at an eighth.
  for (std::size_t k = 1; k < errors.size(); ++k) EXPECT_GT(std::log2(errors[k - 1] / errors[k]), 1.5);
  EXPECT_LT(errors[2], 0.035);
  EXPECT_LT(errors[3], 0.01);
  ibvalve::base::Logger::global().info(table.str());
}

TEST(SelectiveIntegration, CantileverWithSRIApproachesTheContinuumAsTheThicknessIsRefined)
{
  // The one-element modulus E_1 = 2 mu is half the continuum's: a linear element through the
  // thickness cannot make eps_zz follow -eps_xx (= kappa z); SRI leaves that part of tr eps free
  // instead of locking it. With n elements through the thickness E_n -> E' as 1 - 1/(2 n^2).
  const int along = 160;
  const double continuum = timoshenko_deflection(tip_load, continuum_modulus(), 5.0 / 6.0);
  std::ostringstream table;
  table << std::setprecision(4) << "same cantilever, " << along << " elements along:\n"
        << "  through | SRI/continuum | predicted E'/E_n (with parasitic shear) | full/continuum | "
           "predicted E'/E_full,n\n";
  for (int through : {1, 2, 4}) {
    const double sri = tip_deflection(along, through, Integration::selective);
    const double full = tip_deflection(along, through, Integration::full);
    const double predicted = continuum_modulus() / with_parasitic_shear(layered_modulus(through), along);
    const double predicted_full = continuum_modulus() / locked_modulus(through);
    table << "  " << std::setw(7) << through << " | " << std::setw(13) << sri / continuum << " | "
          << std::setw(39) << predicted << " | " << std::setw(14) << full / continuum << " | "
          << predicted_full << "\n";
    // Bending dominates (shear is 0.3 % of the deflection at L/H = 20); the clamp, which holds
    // eps_zz at zero where the moment is largest, stiffens the layered beams by O(H/L) = 5 %
    // of that 5 % (measured: 1.5 %).
    EXPECT_NEAR(sri / continuum, predicted, 0.025 * predicted) << through << " elements through";
    EXPECT_LT(full / continuum, 2.0 * predicted_full) << through << " elements through";
    EXPECT_GT(full / continuum, predicted_full) << through << " elements through";
  }
  ibvalve::base::Logger::global().info(table.str());
}

// The penalty once per element is a constant pressure per element on trilinear displacements (the
// Q1-P0 pair): a displacement whose element-mean dilatation alternates like a checkerboard gives
// element pressures that alternate by lambda x the dilatation, which the fields would show as a
// fiber stress alternating element by element. SolidModel::filtered_centre_stress (node means of the
// element stresses, then element means of the node means) removes that mode and keeps a linear one.
namespace {

struct SheetDisplacement {
  Mesh mesh = box_mesh(CellShape::hexahedron, Vec3(0, 0, 0), Vec3(0.6, 0.6, 0.04), {6, 6, 1});
  static constexpr double h = 0.1;
  /// Elements whose nodes all have four elements of the sheet around them.
  bool interior(std::size_t e) const
  {
    Vec3 centre = Vec3::Zero();
    for (int a : mesh.element(e)) centre += mesh.nodes()[a] / 8.0;
    return centre.x() > h && centre.x() < 5 * h && centre.y() > h && centre.y() < 5 * h;
  }
  /// u_x = amplitude (-1)^(i+j) j at node (i, j): element (i, j)'s mean du_x/dx = amplitude (-1)^(i+j) / h.
  std::vector<double> checkerboard(double amplitude) const
  {
    std::vector<double> u(3 * mesh.num_nodes(), 0.0);
    for (std::size_t n = 0; n < mesh.num_nodes(); ++n) {
      const long i = std::lround(mesh.nodes()[n].x() / h), j = std::lround(mesh.nodes()[n].y() / h);
      u[3 * n] = amplitude * ((i + j) % 2 == 0 ? 1.0 : -1.0) * static_cast<double>(j);
    }
    return u;
  }
  /// u_x = amplitude x^2 / 2: a dilatation linear in x.
  std::vector<double> linear_dilatation(double amplitude) const
  {
    std::vector<double> u(3 * mesh.num_nodes(), 0.0);
    for (std::size_t n = 0; n < mesh.num_nodes(); ++n)
      u[3 * n] = amplitude * 0.5 * std::pow(mesh.nodes()[n].x(), 2);
    return u;
  }
};

} // namespace

TEST(SelectiveIntegration, TheFieldsFilterTheCheckerboardOfTheCentrePressure)
{
  const SheetDisplacement sheet;
  SolidModel model(sheet.mesh, neo_hookean_part(sheet.mesh, Integration::selective), 2, PETSC_COMM_WORLD);
  ibvalve::materials::FiberFrame frame;
  frame.f0 = Vec3(1, 0, 0);
  model.set_fibers(std::vector<ibvalve::materials::FiberFrame>(sheet.mesh.num_elements(), frame));

  // The checkerboard: element dilatations d = +-1e-4 (F = I + d e_x e_x exactly, so J = 1 + d), element
  // pressures lambda ln J / J = +-lambda 1e-4 = +-1e3 dyn/cm^2. The filter leaves their second-order
  // mean, -3/2 lambda d^2 = -0.15 dyn/cm^2 on each diagonal entry (norm sqrt(3) x 0.15); the fields' fiber
  // stress keeps only the full rule's deviatoric response to the mode, 2 mu d = 2 (a thousandth of the
  // pressure's).
  const double eps = 1e-4;
  const std::vector<double> mode = sheet.checkerboard(eps * SheetDisplacement::h);
  const std::vector<Mat3> filtered = model.filtered_centre_stress(mode);
  const ElementFields fields = model.element_fields(mode);
  int checked = 0;
  for (const auto& [p, e] : model.local_items()) {
    if (!sheet.interior(e)) continue;
    const double own = model.centre_cauchy_stress(p, mode, e)(0, 0);
    EXPECT_NEAR(std::abs(own), lambda * eps, 0.01 * lambda * eps) << "element " << e;
    EXPECT_LT(filtered[e].norm(), 2.0 * std::sqrt(3.0) * 1.5 * lambda * eps * eps) << "element " << e;
    EXPECT_LT(std::abs(fields.fiber_stress[e]), 2.0 * 2.0 * mu * eps) << "element " << e;
    ++checked;
  }
  EXPECT_GT(checked, 0); // on 2 ranks each holds some interior elements

  // The mode's pressures move no interior node: the centre laws' nodal forces there cancel to second
  // order, against the lambda eps x (h t / 4) = 1e3 x 1e-3 = 1 dyn one element's pressure puts on a node.
  std::vector<double> all(model.num_dofs()), tissue(model.num_dofs());
  model.forces(mode, all);
  model.forces(mode, tissue, /*centre_laws=*/false);
  const double one_element = lambda * eps * SheetDisplacement::h * 0.04 / 4.0;
  for (std::size_t n = 0; n < sheet.mesh.num_nodes(); ++n) {
    const Vec3& X = sheet.mesh.nodes()[n];
    if (X.x() < 0.5 * SheetDisplacement::h || X.x() > 5.5 * SheetDisplacement::h ||
        X.y() < 0.5 * SheetDisplacement::h || X.y() > 5.5 * SheetDisplacement::h)
      continue;
    for (int i = 0; i < 3; ++i)
      EXPECT_LT(std::abs(all[3 * n + i] - tissue[3 * n + i]), 1e-3 * one_element) << "node " << n;
  }

  // A dilatation linear in x, d = 1e-4 x / cm: the filter keeps each interior element's pressure, up
  // to the second-order term's curvature (lambda 3/2 (1e-4 x)^2 varies by less than lambda 1e-8 across
  // a node's elements).
  const std::vector<double> ramp = sheet.linear_dilatation(eps);
  const std::vector<Mat3> kept = model.filtered_centre_stress(ramp);
  for (const auto& [p, e] : model.local_items()) {
    if (!sheet.interior(e)) continue;
    const Mat3 own = model.centre_cauchy_stress(p, ramp, e);
    EXPECT_GT(std::abs(own(0, 0)), 0.1 * lambda * eps) << "element " << e; // x > 0.1 cm
    EXPECT_LT((kept[e] - own).norm(), std::sqrt(3.0) * lambda * eps * eps) << "element " << e;
  }
}
