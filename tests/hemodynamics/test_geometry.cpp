// Leaflet geometry measures against analytic shapes: the geometric orifice area of three leaflets
// opened to a known circle and of closed leaflets (any axis direction, triangles or quads),
// displacement statistics, sphere averages and fiber strain/stress.
#include <cmath>
#include <iostream>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "hemodynamics/geometry.hpp"

namespace hd = ibvalve::hemodynamics;
using std::numbers::pi;

namespace {

constexpr double R = 1.3; // tube radius, cm

/// Three leaflets (120-degree sectors) covering the annulus r_open <= r <= R of the plane normal to
/// z, warped along z (which the projection must ignore); quads or triangles.
struct Leaflets {
  std::vector<hd::Point> points;
  std::vector<hd::Triangle> triangles;
  std::vector<hd::Quad> quads;
};

Leaflets leaflets(double r_open, int segments_per_leaflet, int rings, bool use_quads)
{
  Leaflets l;
  for (int leaflet = 0; leaflet < 3; ++leaflet) {
    const std::size_t base = l.points.size();
    for (int i = 0; i <= segments_per_leaflet; ++i) {
      const double theta = 2 * pi / 3 * (leaflet + static_cast<double>(i) / segments_per_leaflet);
      for (int j = 0; j <= rings; ++j) {
        const double r = r_open + (R - r_open) * j / rings;
        const double z = 0.4 * (R - r) + 0.1 * std::sin(3 * theta);
        l.points.push_back({r * std::cos(theta), r * std::sin(theta), z});
      }
    }
    auto id = [&](int i, int j) { return base + static_cast<std::size_t>(i * (rings + 1) + j); };
    for (int i = 0; i < segments_per_leaflet; ++i)
      for (int j = 0; j < rings; ++j) {
        if (use_quads) {
          l.quads.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
        } else {
          l.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
          l.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
      }
  }
  return l;
}

/// Rotates points and the axis by a fixed rotation: the area must not change.
Eigen::Matrix3d rotation()
{
  return (Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized())).toRotationMatrix();
}

/// The exact open area: the inner polygon of the leaflets (n sides inscribed in the circle r_open)
/// plus the slivers between the outer polygon (n sides inscribed in R) and the tube wall.
double exact_open_area(double r_open, int n)
{
  auto polygon = [&](double r) { return 0.5 * n * r * r * std::sin(2 * pi / n); };
  return polygon(r_open) + (pi * R * R - polygon(R));
}

} // namespace

TEST(OrificeArea, LeafletsOpenedToAKnownCircle)
{
  const int segments = 128;
  for (double r_open : {0.3, 0.65, 1.0}) {
    // The leaflets' edges are polygons of 3 x 128 sides inscribed in the circles.
    const double exact = exact_open_area(r_open, 3 * segments);
    const Leaflets l = leaflets(r_open, segments, 3, false);
    const double area = hd::geometric_orifice_area(l.points, l.triangles, {}, hd::CrossSection{});
    std::cout << "  r_open " << r_open << ": area " << area << " cm^2, exact " << exact << ", rel. error "
              << area / exact - 1 << "\n";
    EXPECT_NEAR(area / exact, 1.0, 0.01);
    EXPECT_NEAR(area / (pi * r_open * r_open), 1.0, 0.01);
  }
}

TEST(OrificeArea, FullyClosedLeafletsLeaveNoOrifice)
{
  const Leaflets l = leaflets(0.0, 128, 4, false);
  const double area = hd::geometric_orifice_area(l.points, l.triangles, {}, hd::CrossSection{});
  std::cout << "  closed: open area " << area << " cm^2 of a " << pi * R * R << " cm^2 tube (wall slivers "
            << exact_open_area(0.0, 3 * 128) << ")\n";
  EXPECT_LT(area, 0.01 * pi * R * R);
  EXPECT_NEAR(area, exact_open_area(0.0, 3 * 128), 0.01 * exact_open_area(0.0, 3 * 128) + 1e-4);
  // With no leaflets at all the whole tube is open.
  const double empty = hd::geometric_orifice_area({}, {}, {}, hd::CrossSection{});
  EXPECT_NEAR(empty / (pi * R * R), 1.0, 1e-3);
}

TEST(OrificeArea, IndependentOfAxisDirectionAndFaceType)
{
  const double r_open = 0.65;
  const Leaflets tri = leaflets(r_open, 128, 3, false), quad = leaflets(r_open, 128, 3, true);
  const double reference = hd::geometric_orifice_area(tri.points, tri.triangles, {}, hd::CrossSection{});
  EXPECT_NEAR(hd::geometric_orifice_area(quad.points, {}, quad.quads, hd::CrossSection{}) / reference, 1.0,
              1e-3);
  // Rotate and shift everything, axis included.
  const Eigen::Matrix3d Q = rotation();
  const Eigen::Vector3d shift(0.5, -2.0, 7.0);
  std::vector<hd::Point> moved;
  for (const auto& p : tri.points) {
    const Eigen::Vector3d x = Q * Eigen::Vector3d(p[0], p[1], p[2]) + shift;
    moved.push_back({x.x(), x.y(), x.z()});
  }
  const Eigen::Vector3d axis = Q * Eigen::Vector3d::UnitZ();
  hd::CrossSection section{{shift.x(), shift.y(), shift.z()}, {axis.x(), axis.y(), axis.z()}, R};
  const double rotated = hd::geometric_orifice_area(moved, tri.triangles, {}, section);
  std::cout << "  rotated axis: " << rotated << " vs " << reference << "\n";
  EXPECT_NEAR(rotated / reference, 1.0, 5e-3);
}

TEST(OrificeArea, ConvergesWithResolution)
{
  const double r_open = 0.65;
  const double exact = exact_open_area(r_open, 3 * 128);
  const Leaflets l = leaflets(r_open, 128, 3, false);
  double previous = 1.0;
  for (int resolution : {64, 256, 1024, 4096}) {
    const double error = std::abs(
        hd::geometric_orifice_area(l.points, l.triangles, {}, hd::CrossSection{}, {resolution}) / exact - 1);
    std::cout << "  resolution " << resolution << ": rel. error " << error << "\n";
    EXPECT_LT(error, previous);
    previous = error;
  }
}

TEST(LeafletMeasures, DisplacementStatistics)
{
  std::vector<hd::Point> X{{1, 0, 0}, {0, 2, 0}, {0, 0, 3}, {1, 1, 1}};
  std::vector<hd::Point> x = X;
  for (auto& p : x) p[1] += 0.25;
  auto s = hd::displacement_statistics(X, x);
  EXPECT_NEAR(s.mean, 0.25, 1e-15);
  EXPECT_NEAR(s.max, 0.25, 1e-15);
  // Rotation by theta about z: |u| = 2 r sin(theta / 2) with r the distance to the axis.
  const double theta = 0.3;
  x.clear();
  double mean = 0, max = 0;
  for (const auto& p : X) {
    x.push_back({p[0] * std::cos(theta) - p[1] * std::sin(theta),
                 p[0] * std::sin(theta) + p[1] * std::cos(theta), p[2]});
    const double u = 2 * std::hypot(p[0], p[1]) * std::sin(theta / 2);
    mean += u / X.size();
    max = std::max(max, u);
  }
  s = hd::displacement_statistics(X, x);
  EXPECT_NEAR(s.mean, mean, 1e-14);
  EXPECT_NEAR(s.max, max, 1e-14);
}

TEST(LeafletMeasures, SphereAverageOfALinearFieldIsItsCentreValue)
{
  std::vector<hd::Point> points;
  std::vector<double> values, weights;
  const double h = 0.02;
  for (int i = -20; i <= 20; ++i)
    for (int j = -20; j <= 20; ++j)
      for (int k = -20; k <= 20; ++k) {
        const double x = i * h, y = j * h, z = k * h;
        points.push_back({x, y, z});
        values.push_back(2.0 + 3.0 * x - 1.5 * y + 0.5 * z);
        weights.push_back(h * h * h);
      }
  const hd::Point centre{0.1, -0.06, 0.04}; // a lattice point: the sphere's points are symmetric about it
  const auto a = hd::sphere_average(points, values, weights, centre, 0.15);
  const auto b = hd::sphere_average(points, values, {}, centre, 0.15);
  EXPECT_NEAR(a.mean, 2.0 + 0.3 + 0.09 + 0.02, 1e-12);
  EXPECT_NEAR(b.mean, a.mean, 1e-12);
  EXPECT_EQ(a.count, b.count);
  // The lattice points inside a sphere of radius 0.15 = 7.5 h approximate its volume.
  EXPECT_NEAR(a.weight / (4.0 / 3.0 * pi * 0.15 * 0.15 * 0.15), 1.0, 0.03);
  EXPECT_TRUE(std::isnan(hd::sphere_average(points, values, {}, {5, 5, 5}, 0.15).mean));
}

TEST(LeafletMeasures, FiberStrainAndStress)
{
  const double lambda = 1.2;
  Eigen::Matrix3d F = Eigen::Vector3d(lambda, 1 / std::sqrt(lambda), 1 / std::sqrt(lambda)).asDiagonal();
  EXPECT_NEAR(hd::fiber_strain(F, Eigen::Vector3d::UnitX()), (lambda * lambda - 1) / 2, 1e-15);
  const Eigen::Vector3d diagonal = Eigen::Vector3d(1, 1, 0).normalized();
  EXPECT_NEAR(hd::fiber_strain(F, diagonal), ((lambda * lambda - 1) + (1 / lambda - 1)) / 4, 1e-15);
  const Eigen::Matrix3d sigma = Eigen::Vector3d(50.0, 5.0, 0.0).asDiagonal();
  EXPECT_NEAR(hd::fiber_stress(sigma, F, Eigen::Vector3d::UnitX()), lambda * lambda * 50.0, 1e-12);
  // Objectivity: a rotation after the deformation changes neither (sigma rotates with it).
  const Eigen::Matrix3d Q = rotation();
  EXPECT_NEAR(hd::fiber_strain(Q * F, diagonal), hd::fiber_strain(F, diagonal), 1e-14);
  EXPECT_NEAR(hd::fiber_stress(Q * sigma * Q.transpose(), Q * F, diagonal),
              hd::fiber_stress(sigma, F, diagonal), 1e-11);
}
