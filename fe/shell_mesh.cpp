#include "fe/shell_mesh.hpp"

#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>
#include <tuple>

#include <Eigen/Geometry>

namespace ibvalve::fe {

fe::Mesh spherical_shell_mesh(const fe::Vec3& center, double r_inner, double r_outer, int n, int layers)
{
  if (!(r_inner > 0.0 && r_outer > r_inner) || n < 1 || layers < 1)
    throw std::invalid_argument("spherical shell: need 0 < r_inner < r_outer, n >= 1 and layers >= 1");
  std::vector<fe::Vec3> nodes;
  std::map<std::tuple<long, long, long>, int> index;
  const double tolerance = 1e-9 * r_outer;
  auto node = [&](const fe::Vec3& x) {
    const auto key = std::make_tuple(std::lround(x[0] / tolerance), std::lround(x[1] / tolerance),
                                     std::lround(x[2] / tolerance));
    const auto [it, inserted] = index.emplace(key, static_cast<int>(nodes.size()));
    if (inserted) nodes.push_back(x);
    return it->second;
  };
  // Direction on the unit sphere of the point (a, b) in [-1, 1]^2 of cube face (axis, side).
  auto direction = [](int axis, int side, double a, double b) {
    const double ta = std::tan(0.25 * std::numbers::pi * a), tb = std::tan(0.25 * std::numbers::pi * b);
    fe::Vec3 p;
    p[axis] = side;
    p[(axis + 1) % 3] = ta;
    p[(axis + 2) % 3] = tb;
    return p.normalized();
  };
  std::vector<int> connectivity;
  for (int axis = 0; axis < 3; ++axis)
    for (int side : {-1, 1})
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
          for (int k = 0; k < layers; ++k) {
            std::array<int, 8> hex{};
            const int corner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
            for (int layer = 0; layer < 2; ++layer) {
              const double r = r_inner + (r_outer - r_inner) * (k + layer) / layers;
              for (int c = 0; c < 4; ++c) {
                const double a = -1.0 + 2.0 * (i + corner[c][0]) / n, b = -1.0 + 2.0 * (j + corner[c][1]) / n;
                hex[4 * layer + c] = node(center + r * direction(axis, side, a, b));
              }
            }
            // Gmsh's hexahedron wants (bottom 0-3 counter-clockwise seen from the top, top 4-7) a
            // positive Jacobian; on the side = -1 faces the patch's (a, b) frame is left-handed.
            const fe::Vec3 e1 = nodes[hex[1]] - nodes[hex[0]], e2 = nodes[hex[3]] - nodes[hex[0]],
                           e3 = nodes[hex[4]] - nodes[hex[0]];
            if (e1.cross(e2).dot(e3) < 0.0) {
              std::swap(hex[1], hex[3]);
              std::swap(hex[5], hex[7]);
            }
            connectivity.insert(connectivity.end(), hex.begin(), hex.end());
          }
  fe::Mesh mesh(fe::CellShape::hexahedron, std::move(nodes), std::move(connectivity));
  std::vector<int> all(mesh.num_elements());
  for (std::size_t e = 0; e < all.size(); ++e) all[e] = static_cast<int>(e);
  mesh.add_volume_group("body", all);
  const double middle = 0.5 * (r_inner + r_outer);
  mesh.add_boundary_group("inner", [&](const fe::Vec3& x) { return (x - center).norm() < middle; });
  mesh.add_boundary_group("outer", [&](const fe::Vec3& x) { return (x - center).norm() > middle; });
  return mesh;
}

} // namespace ibvalve::fe
