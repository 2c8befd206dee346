// The generated aortic valve: a valid hexahedral mesh (every element positively oriented), the groups
// the fiber rules and the run need, the stated geometry, and a closed state that covers the orifice
// but for the stated gap.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "fe/valve_mesh.hpp"

namespace ibvalve::fe {
namespace {

/// det of the Jacobian of a trilinear hexahedron at each corner (Gmsh ordering): all must be > 0.
double smallest_corner_jacobian(const Mesh& mesh, std::size_t e)
{
  static const int neighbours[8][3] = {{1, 3, 4}, {2, 0, 5}, {3, 1, 6}, {0, 2, 7},
                                       {7, 5, 0}, {4, 6, 1}, {5, 7, 2}, {6, 4, 3}};
  const auto nodes = mesh.element(e);
  double smallest = INFINITY;
  for (int c = 0; c < 8; ++c) {
    const Vec3& x = mesh.nodes()[nodes[c]];
    const Vec3 a = mesh.nodes()[nodes[neighbours[c][0]]] - x, b = mesh.nodes()[nodes[neighbours[c][1]]] - x,
               d = mesh.nodes()[nodes[neighbours[c][2]]] - x;
    smallest = std::min(smallest, a.cross(b).dot(d));
  }
  return smallest;
}

TEST(AorticValveMesh, EveryElementIsPositivelyOriented)
{
  const Mesh mesh = aortic_valve_mesh({});
  for (std::size_t e = 0; e < mesh.num_elements(); ++e)
    ASSERT_GT(smallest_corner_jacobian(mesh, e), 0.0) << e;
}

TEST(AorticValveMesh, HasTheGroupsTheFiberRulesAndTheRunNeed)
{
  const Mesh mesh = aortic_valve_mesh({});
  for (int k = 1; k <= 3; ++k)
    for (const char* suffix :
         {"", "_attachment", "_tau1", "_tau2", "_n1", "_n2", "_free_edge", "_commissure1", "_commissure2"})
      EXPECT_TRUE(mesh.has_group("leaflet" + std::to_string(k) + suffix)) << k << suffix;
  for (const char* name : {"tube", "tube_outer", "tube_inner", "tube_inlet", "tube_outlet"})
    EXPECT_TRUE(mesh.has_group(name)) << name;
  const ValveMeshParameters p;
  EXPECT_EQ(mesh.group("leaflet1").elements.size(),
            static_cast<std::size_t>(p.leaflet_across * p.leaflet_radial * p.leaflet_through));
  EXPECT_EQ(mesh.group("tube").elements.size(),
            static_cast<std::size_t>(p.tube_around * p.tube_along * p.tube_through));
  // The FD2 halves split the attachment: together they are all of it.
  const auto& attachment = mesh.group("leaflet2_attachment");
  EXPECT_EQ(mesh.group("leaflet2_tau1").cells.size() + mesh.group("leaflet2_tau2").cells.size(),
            attachment.cells.size());
}

TEST(AorticValveMesh, GeometryFollowsTheParameters)
{
  const ValveMeshParameters p;
  const Mesh mesh = aortic_valve_mesh(p);
  // The attachment's mid-surface lies on the tube's inner wall.
  for (int n : mesh.group("leaflet1_attachment").nodes) {
    const Vec3& x = mesh.nodes()[n];
    EXPECT_NEAR(std::hypot(x[0], x[1]), p.tube_radius, p.leaflet_thickness / 2 + 1e-12);
  }
  // FD1's points are the free edge's ends, at the commissures (on the wall, at the commissure height).
  for (const char* end : {"leaflet3_n1", "leaflet3_n2"})
    for (int n : mesh.group(end).nodes) {
      const Vec3& x = mesh.nodes()[n];
      EXPECT_NEAR(x[2], p.valve_base + p.commissure_height, p.leaflet_thickness) << end;
      EXPECT_NEAR(std::hypot(x[0], x[1]), p.tube_radius, p.leaflet_thickness / 2 + 1e-12) << end;
    }
  // The tube: inner and outer radius, length.
  for (int n : mesh.group("tube_outer").nodes)
    EXPECT_NEAR(std::hypot(mesh.nodes()[n][0], mesh.nodes()[n][1]), p.tube_radius + p.tube_wall, 1e-12);
  double z_max = 0;
  for (int n : mesh.group("tube_outlet").nodes) z_max = std::max(z_max, mesh.nodes()[n][2]);
  EXPECT_NEAR(z_max, p.tube_length, 1e-12);
  // The tube's volume converges to the annulus' at second order in the angular spacing (polygonal wall).
  const double annulus = std::numbers::pi *
                         (std::pow(p.tube_radius + p.tube_wall, 2) - p.tube_radius * p.tube_radius) *
                         p.tube_length;
  Mesh tube_only = submesh(mesh, mesh.group("tube").elements);
  const double dtheta = 2 * std::numbers::pi / p.tube_around;
  EXPECT_NEAR(tube_only.volume() / annulus, 1.0, dtheta * dtheta);
}

TEST(AorticValveMesh, ClosedLeafletsCoverTheOrificeButForTheGap)
{
  // Rasterise the axial projection of the leaflets' elements (each hexahedron's projection is the
  // convex hull of its corners; points are tested against its two triangles of each face pair) on a
  // fine grid over the orifice, and compare the uncovered area with the three gap strips of width
  // free_edge_gap along the coaptation lines.
  ValveMeshParameters p;
  p.include_tube = false;
  const Mesh mesh = aortic_valve_mesh(p);
  const int n = 500;
  const double R = p.tube_radius, h = 2 * R / n;
  std::vector<char> covered(n * n, 0);
  auto cell_of = [&](double v) { return static_cast<int>(std::floor((v + R) / h)); };
  for (std::size_t e = 0; e < mesh.num_elements(); ++e) {
    const auto nodes = mesh.element(e);
    // Project the top and bottom quadrilaterals (mid-surface-parallel faces) and fill each.
    for (int face = 0; face < 2; ++face) {
      std::array<Eigen::Vector2d, 4> q;
      for (int a = 0; a < 4; ++a) q[a] = mesh.nodes()[nodes[4 * face + a]].head<2>();
      double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
      for (const auto& v : q)
        for (int d = 0; d < 2; ++d) lo[d] = std::min(lo[d], v[d]), hi[d] = std::max(hi[d], v[d]);
      for (int i = std::max(0, cell_of(lo[0])); i <= std::min(n - 1, cell_of(hi[0])); ++i)
        for (int j = std::max(0, cell_of(lo[1])); j <= std::min(n - 1, cell_of(hi[1])); ++j) {
          const Eigen::Vector2d x(-R + (i + 0.5) * h, -R + (j + 0.5) * h);
          auto inside = [&](int a, int b, int c) {
            auto side = [](const Eigen::Vector2d& u, const Eigen::Vector2d& v, const Eigen::Vector2d& w) {
              return (v - u).x() * (w - u).y() - (v - u).y() * (w - u).x();
            };
            const double s1 = side(q[a], q[b], x), s2 = side(q[b], q[c], x), s3 = side(q[c], q[a], x);
            return (s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0);
          };
          if (inside(0, 1, 2) || inside(0, 2, 3)) covered[i * n + j] = 1;
        }
    }
  }
  double open_area = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double x = -R + (i + 0.5) * h, y = -R + (j + 0.5) * h;
      if (x * x + y * y < R * R && !covered[i * n + j]) {
        open_area += h * h;
      }
    }
  // At most the three strips between neighbouring free edges (the leaflets' thickness covers part of
  // them), plus the raster's error (a cell along each strip and around the wall), and below the
  // 0.1 cm^2 a closed valve may leak through.
  const double strips = 3 * R * p.free_edge_gap;
  const double raster = 3 * R * h + 2 * std::numbers::pi * R * h;
  EXPECT_LT(open_area, strips + raster) << "open " << open_area << " cm^2";
  EXPECT_LT(open_area, 0.1);
  std::printf("closed valve: open area %.4f cm^2 (strips %.4f cm^2)\n", open_area, strips);
  EXPECT_LT(open_area, 0.1);
}

TEST(AorticValveMesh, BadParametersAreRefusedByName)
{
  ValveMeshParameters p;
  p.leaflet_across = 7;
  EXPECT_THROW(check(p), std::invalid_argument);
  p = {};
  p.free_edge_gap = 2.0;
  EXPECT_THROW(check(p), std::invalid_argument);
  p = {};
  p.valve_base = 12.5;
  EXPECT_THROW(check(p), std::invalid_argument);
}

} // namespace
} // namespace ibvalve::fe
