// The leaflet state the aortic-valve model writes each row (app/leaflet_state.hpp): the spheres sit
// where the geometry puts them, and on homogeneous deformations the row has its closed forms, the same
// on 1 and 2 ranks.
#include <cmath>
#include <memory>

#include <gtest/gtest.h>
#include <petscsys.h>

#include "app/leaflet_state.hpp"
#include "base/units.hpp"
#include "fe/valve_mesh.hpp"
#include "tests/fe/neo_hookean_fixture.hpp"

using namespace ibvalve;

namespace {

struct Valve {
  fe::ValveMeshParameters geometry;
  fe::Mesh mesh;
  std::unique_ptr<fe::SolidModel> solid;
  double mu = 2e4, lambda = 1e5; // dyn/cm^2

  Valve()
  {
    geometry.tube_length = 5.0;
    geometry.valve_base = 2.0;
    geometry.free_edge_drop = 0.5;
    geometry.leaflet_across = 24;
    geometry.leaflet_radial = 10;
    geometry.tube_around = 32;
    geometry.tube_along = 10;
    mesh = fe::aortic_valve_mesh(geometry);
    std::vector<fe::BodyPart> parts;
    auto law = std::make_shared<fe::fixtures::NeoHookeanFixture>(mu, lambda);
    for (const char* name : {"leaflet1", "leaflet2", "leaflet3", "tube"})
      parts.push_back(fe::BodyPart{name, mesh.group(name).elements, {law}});
    solid = std::make_unique<fe::SolidModel>(mesh, parts, 2, PETSC_COMM_WORLD);
    // Fibers along the attachment's circumference, any unit vector serves the closed forms below.
    std::vector<materials::FiberFrame> frames(mesh.num_elements());
    for (std::size_t e = 0; e < frames.size(); ++e) frames[e].f0 = fe::Vec3(1.0, 2.0, 2.0) / 3.0;
    solid->set_fibers(frames);
  }
};

} // namespace

TEST(LeafletState, SpheresSitAtEachLeafletsBellyAndFreeEdgeCentre)
{
  const Valve valve;
  const app::LeafletState state(*valve.solid, 3, valve.geometry.leaflet_thickness);
  ASSERT_EQ(state.belly().size(), 3u);
  for (int k = 0; k < 3; ++k) {
    const fe::Vec3 top = state.top()[k].centre, belly = state.belly()[k].centre;
    // The top-centre is the free edge's middle: at the valve's centre, at the closed free edge's
    // height there (commissures less the drop).
    EXPECT_LT(std::hypot(top[0], top[1]), valve.geometry.free_edge_gap) << k;
    EXPECT_NEAR(top[2],
                valve.geometry.valve_base + valve.geometry.commissure_height - valve.geometry.free_edge_drop,
                valve.geometry.leaflet_thickness)
        << k;
    // The belly lies in the leaflet's plane of symmetry (its centre direction, 90 + 120 k degrees),
    // between the wall and the centre, above the nadir and below the free edge.
    const double angle = (90.0 + 120.0 * k) * std::acos(-1.0) / 180.0;
    EXPECT_NEAR(-std::sin(angle) * belly[0] + std::cos(angle) * belly[1], 0.0, 0.06) << k;
    const double r = std::cos(angle) * belly[0] + std::sin(angle) * belly[1];
    EXPECT_GT(r, 0.3 * valve.geometry.tube_radius) << k;
    EXPECT_LT(r, 0.7 * valve.geometry.tube_radius) << k;
    EXPECT_GT(belly[2], valve.geometry.valve_base);
    EXPECT_LT(belly[2], top[2]);
    EXPECT_GT(state.belly()[k].points.size(), 8u) << k;
    EXPECT_GT(state.top()[k].points.size(), 4u) << k;
  }
  EXPECT_NE(state.describe().find("leaflet3 belly"), std::string::npos);
}

TEST(LeafletState, RowsHaveTheClosedFormsOfATranslationAndADilation)
{
  const Valve valve;
  const app::LeafletState state(*valve.solid, 3, valve.geometry.leaflet_thickness);
  const std::size_t nodes = valve.mesh.num_nodes();

  // A rigid translation by d: every leaflet node moves |d|; no strain, no stress.
  std::vector<double> u(3 * nodes);
  for (std::size_t n = 0; n < nodes; ++n) {
    u[3 * n] = 0.03;
    u[3 * n + 1] = -0.04;
    u[3 * n + 2] = 0.12;
  }
  const std::vector<double> moved = state.row(u, 250.0);
  ASSERT_EQ(moved.size(), 7u);
  EXPECT_NEAR(moved[0], 0.13, 1e-12);
  EXPECT_NEAR(moved[1], 0.13, 1e-12);
  EXPECT_EQ(moved[2], 250.0);
  for (int c = 3; c < 7; ++c) EXPECT_NEAR(moved[c], 0.0, 1e-9) << c;

  // The dilation x = s X: node n moves (s - 1)|X_n|; every fiber strain is (s^2 - 1)/2, and the
  // fiber stress f . (sigma f) with f = F f0 = s f0 is s^2 times the Cauchy stress
  // sigma = (mu (s^2 - 1) + lambda ln s^3) / s^3 of the neo-Hookean law.
  const double s = 1.08;
  double mean = 0.0, largest = 0.0;
  std::size_t count = 0;
  for (const char* name : {"leaflet1", "leaflet2", "leaflet3"})
    for (int n : valve.mesh.group(name).nodes) {
      const double d = (s - 1.0) * valve.mesh.nodes()[n].norm();
      mean += d;
      largest = std::max(largest, d);
      ++count;
    }
  for (std::size_t n = 0; n < nodes; ++n)
    for (int i = 0; i < 3; ++i) u[3 * n + i] = (s - 1.0) * valve.mesh.nodes()[n][i];
  const std::vector<double> dilated = state.row(u, 0.0);
  EXPECT_NEAR(dilated[0], mean / static_cast<double>(count), 1e-12);
  EXPECT_NEAR(dilated[1], largest, 1e-12);
  const double strain = 0.5 * (s * s - 1.0);
  const double sigma = (valve.mu * (s * s - 1.0) + valve.lambda * std::log(s * s * s)) / (s * s * s);
  EXPECT_NEAR(dilated[3], strain, 1e-12);
  EXPECT_NEAR(dilated[4], strain, 1e-12);
  EXPECT_NEAR(dilated[5], s * s * sigma / units::kPa, 1e-9);
  EXPECT_NEAR(dilated[6], s * s * sigma / units::kPa, 1e-9);
}
