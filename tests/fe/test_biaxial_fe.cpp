// One-element planar biaxial test of every law of materials/ through the FE force assembly: a unit
// cube (one hexahedron, or six tetrahedra) deformed homogeneously by F = diag(l1, l2, 1/(l1 l2)).
// The nodal forces on the face X_i = 1 sum to -P e_i (sum over that face of N_a is X_i, whose gradient
// is e_i), which gives P, then sigma = P F^T / J with sigma33 = 0 imposed by the hydrostatic pressure
// (subtract sigma33). This must equal the planar-biaxial analytics of materials/biaxial.hpp
// (docs/reference.md, "Constitutive fitting") to round-off: < 1e-8 relative.
#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>

#include <gtest/gtest.h>

#include "base/logger.hpp"
#include "fe/solid.hpp"
#include "materials/biaxial.hpp"
#include "materials/law.hpp"
#include "materials/material.hpp"

using namespace ibvalve;
using fe::Vec3;

namespace {

struct Case {
  materials::LawKind law;
  std::vector<double> parameters_kpa_or_1; // moduli in kPa
  double fiber_angle;
};

// The study's fitted means (docs/reference.md, "Constitutive laws"); neo-Hookean and HGO with typical values.
const std::vector<Case> cases{
    {materials::LawKind::neo_hookean, {10.0}, 0.0},
    {materials::LawKind::W1, {1.21, 7.99, 24.23, 57.62}, 0.0},
    {materials::LawKind::W2, {1.18, 55.04, 8.08, 54.00}, 0.0},
    {materials::LawKind::W3, {19.59, 12.94, 77.79}, 0.0},
    {materials::LawKind::hgo, {3.0, 23.6, 8.4, 0.1}, 0.7},
};

std::vector<double> to_cgs(const Case& c)
{
  std::vector<double> p = c.parameters_kpa_or_1;
  const auto& info = materials::law_info(c.law);
  for (std::size_t i = 0; i < p.size(); ++i)
    if (info.parameters[i].is_modulus) p[i] *= 1e4; // kPa -> dyn/cm^2
  return p;
}

} // namespace

class BiaxialFe : public ::testing::TestWithParam<fe::CellShape> {};

TEST_P(BiaxialFe, OneElementStressesMatchTheBiaxialAnalytics)
{
  const fe::Mesh mesh = fe::box_mesh(GetParam(), Vec3(0, 0, 0), Vec3(1, 1, 1), {1, 1, 1});
  double worst = 0;
  for (const Case& c : cases) {
    const std::vector<double> p = to_cgs(c);
    materials::BiaxialSetup setup;
    setup.law = c.law;
    setup.fiber_angle = c.fiber_angle;
    // The law with its reference-state term and a volumetric penalty: both are hydrostatic at J = 1.
    auto law = std::make_shared<materials::InvariantLaw>(c.law, p);
    auto material = std::make_shared<materials::Material>(
        law, materials::VolumetricPenalty(materials::PenaltyKind::log, 1e6));
    fe::SolidModel solid(mesh, {fe::BodyPart{"sample", mesh.group("body").elements, {material}}}, 2,
                         PETSC_COMM_WORLD);
    solid.set_fibers(
        std::vector<materials::FiberFrame>(mesh.num_elements(), materials::biaxial_frame(setup)));
    for (const auto& [l1, l2] : {std::pair{1.05, 1.02}, std::pair{1.12, 1.08}, std::pair{1.2, 1.0}}) {
      const Eigen::Vector3d stretch(l1, l2, 1 / (l1 * l2));
      std::vector<double> u(3 * mesh.num_nodes());
      for (std::size_t n = 0; n < mesh.num_nodes(); ++n)
        for (int i = 0; i < 3; ++i) u[3 * n + i] = (stretch[i] - 1) * mesh.nodes()[n][i];
      std::vector<double> f(u.size());
      solid.forces(u, f);
      Eigen::Matrix3d P;
      const char* faces[3] = {"xmax", "ymax", "zmax"};
      for (int j = 0; j < 3; ++j) {
        Vec3 sum = Vec3::Zero();
        for (int n : mesh.group(faces[j]).nodes) sum += Vec3(f[3 * n], f[3 * n + 1], f[3 * n + 2]);
        P.col(j) = -sum;
      }
      const Eigen::Matrix3d F = stretch.asDiagonal();
      const Eigen::Matrix3d sigma = P * F.transpose() / F.determinant();
      const auto analytic = materials::biaxial_cauchy<double>(setup, p.data(), l1, l2);
      const double s11 = sigma(0, 0) - sigma(2, 2), s22 = sigma(1, 1) - sigma(2, 2);
      const double scale = std::max(std::abs(analytic[0]), std::abs(analytic[1]));
      EXPECT_LT(std::abs(s11 - analytic[0]) / scale, 1e-8)
          << materials::law_info(c.law).name << " " << l1 << " " << l2;
      EXPECT_LT(std::abs(s22 - analytic[1]) / scale, 1e-8)
          << materials::law_info(c.law).name << " " << l1 << " " << l2;
      worst = std::max({worst, std::abs(s11 - analytic[0]) / scale, std::abs(s22 - analytic[1]) / scale});
      // No shear in the biaxial frame.
      EXPECT_LT(std::abs(sigma(0, 1)) / scale, 1e-8);
    }
  }
  std::ostringstream message;
  message << "one-element biaxial (" << mesh.type().name() << "), all laws: largest relative stress error "
          << worst;
  base::Logger::global().info(message.str());
}

INSTANTIATE_TEST_SUITE_P(HexAndTet, BiaxialFe,
                         ::testing::Values(fe::CellShape::hexahedron, fe::CellShape::tetrahedron));
