// An inverted element corner (docs/fe.md, "Inverted element corners"): the solid's smallest
// quadrature-point J (fe::SolidModel::smallest_point_jacobian, diagnostics.csv's smallest_J) has its
// closed form and names the element, the same on 1 and 2 ranks, and the run's watch (app/ibfe_fields.hpp)
// warns once each time J goes from above zero to zero or below.
//
// Two unit cubes side by side, [0, 2] x [0, 1] x [0, 1]; the far top corner (2, 1, 1) pushed down by d.
// In that cube's local coordinates (x, y, z) in [0, 1]^3 the displacement is u_z = -d x y z (the
// corner's trilinear shape function), so F = I + grad u has rows (1, 0, 0), (0, 1, 0),
// (-d y z, -d x z, 1 - d x y) and J = 1 - d x y: smallest at the Gauss point nearest the corner,
// x = y = g = 1/2 + 1/(2 sqrt 3), J = 1 - d g^2, while the element's mean J is 1 - d/4.
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <petscsys.h>
#include <unistd.h>

#include "app/ibfe_fields.hpp"
#include "base/logger.hpp"
#include "fe/solid.hpp"
#include "io/files.hpp"
#include "tests/fe/neo_hookean_fixture.hpp"

using namespace ibvalve;

namespace {

struct TwoCubes {
  fe::Mesh mesh = fe::box_mesh(fe::CellShape::hexahedron, fe::Vec3(0, 0, 0), fe::Vec3(2, 1, 1), {2, 1, 1});
  std::unique_ptr<fe::SolidModel> solid;
  int corner = -1;  // the node at (2, 1, 1)
  int element = -1; // the cube that holds it

  TwoCubes()
  {
    auto law = std::make_shared<fe::fixtures::NeoHookeanFixture>(1e4, 1e5);
    solid = std::make_unique<fe::SolidModel>(
        mesh, std::vector<fe::BodyPart>{{"leaflet", mesh.group("body").elements, {law}}}, 2,
        PETSC_COMM_WORLD);
    for (std::size_t a = 0; a < mesh.num_nodes(); ++a)
      if ((mesh.nodes()[a] - fe::Vec3(2, 1, 1)).norm() < 1e-12) corner = static_cast<int>(a);
    for (std::size_t e = 0; e < mesh.num_elements(); ++e)
      for (int node : mesh.element(e))
        if (node == corner) element = static_cast<int>(e);
  }

  std::vector<double> corner_pushed_down(double d) const
  {
    std::vector<double> u(3 * mesh.num_nodes(), 0.0);
    u[3 * corner + 2] = -d;
    return u;
  }
};

const double g = 0.5 + 0.5 / std::sqrt(3.0); // the Gauss point nearest a corner, in [0, 1]

TEST(SmallestPointJacobian, IsOneMinusDTimesTheGaussPointsXYAndNamesTheElement)
{
  TwoCubes cubes;
  ASSERT_GE(cubes.corner, 0);
  EXPECT_EQ(cubes.solid->smallest_point_jacobian(cubes.corner_pushed_down(0.0)).J, 1.0);
  for (const double d : {0.5, 1.6, 2.5}) {
    const fe::SmallestJacobian s = cubes.solid->smallest_point_jacobian(cubes.corner_pushed_down(d));
    EXPECT_NEAR(s.J, 1.0 - d * g * g, 1e-14) << "d = " << d;
    EXPECT_EQ(s.element, cubes.element);
    // The element's mean J stays positive while the corner inverts (d = 2.5: J = -0.55, mean 0.375).
    EXPECT_GT(1.0 - d / 4.0, 0.0);
  }
}

TEST(InversionWatch, WarnsOnceEachTimeThePointJacobianReachesZero)
{
  TwoCubes cubes;
  int rank = 0, pid = static_cast<int>(::getpid());
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  MPI_Bcast(&pid, 1, MPI_INT, 0, PETSC_COMM_WORLD);
  const auto path = std::filesystem::temp_directory_path() / fmt::format("ibvalve_inversion_{}.txt", pid);
  base::Logger& log = base::Logger::global();
  log.open_file(path);
  ::testing::internal::CaptureStderr();
  app::InversionWatch watch(*cubes.solid);
  // J over the steps: positive, inverted for two steps, back, inverted again.
  const double pushes[] = {0.5, 1.8, 2.5, 1.0, 2.0};
  for (int step = 0; step < 5; ++step)
    watch.observe(0.1 * step, cubes.solid->smallest_point_jacobian(cubes.corner_pushed_down(pushes[step])));
  const std::string err = ::testing::internal::GetCapturedStderr();
  log.close_file();
  if (rank == 0) {
    const std::string text = io::read_text_file(path);
    std::size_t warnings = 0;
    for (std::size_t at = text.find("is inverted"); at != std::string::npos;
         at = text.find("is inverted", at + 1))
      ++warnings;
    EXPECT_EQ(warnings, 2u) << text;
    EXPECT_NE(text.find(fmt::format("t = 0.1 s: element {} (leaflet, reference centre (1.5, 0.5, 0.5) cm)",
                                    cubes.element)),
              std::string::npos)
        << text;
    EXPECT_NE(text.find(fmt::format("J = {:.3g}", 1.0 - 1.8 * g * g)), std::string::npos) << text;
    EXPECT_NE(text.find("t = 0.4 s"), std::string::npos) << text;
    EXPECT_NE(err.find("warning: t = 0.1 s"), std::string::npos) << err;
    std::filesystem::remove(path);
  }
}

} // namespace
