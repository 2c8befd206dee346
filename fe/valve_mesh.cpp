#include "fe/valve_mesh.hpp"

#include <cmath>
#include <fmt/format.h>
#include <numbers>
#include <stdexcept>

namespace ibvalve::fe {

namespace {

constexpr double pi = std::numbers::pi;

/// Appends `part` to `into`, its groups renamed by `rename` (a group whose new name is empty is dropped).
void append(Mesh& into, const Mesh& part, const std::function<std::string(const std::string&)>& rename)
{
  const int node_offset = static_cast<int>(into.num_nodes());
  const int element_offset = static_cast<int>(into.num_elements());
  std::vector<Vec3> nodes = into.nodes();
  nodes.insert(nodes.end(), part.nodes().begin(), part.nodes().end());
  std::vector<int> connectivity = into.connectivity();
  for (int n : part.connectivity()) connectivity.push_back(n + node_offset);
  std::vector<PhysicalGroup> groups = into.groups();
  into = Mesh(CellShape::hexahedron, std::move(nodes), std::move(connectivity));
  for (PhysicalGroup& g : groups) into.add_group(std::move(g));
  for (PhysicalGroup g : part.groups()) {
    g.name = rename(g.name);
    if (g.name.empty()) continue;
    g.tag = -1;
    for (int& e : g.elements) e += element_offset;
    for (int& c : g.cells) c += node_offset;
    g.nodes.clear();
    into.add_group(std::move(g));
  }
}

/// Reverses the orientation of every hexahedron (swaps its bottom and top faces) when the map made it
/// negative, so that every element has a positive Jacobian.
void orient_positively(Mesh& mesh)
{
  const auto& x = mesh.nodes();
  auto e = mesh.element(0);
  const double volume = (x[e[1]] - x[e[0]]).cross(x[e[3]] - x[e[0]]).dot(x[e[4]] - x[e[0]]);
  if (volume > 0) return;
  std::vector<int> connectivity = mesh.connectivity();
  for (std::size_t c = 0; c < connectivity.size(); c += 8)
    for (int a = 0; a < 4; ++a) std::swap(connectivity[c + a], connectivity[c + a + 4]);
  std::vector<PhysicalGroup> groups = mesh.groups();
  Mesh flipped(CellShape::hexahedron, mesh.nodes(), std::move(connectivity));
  for (PhysicalGroup& g : groups) {
    // Boundary-face orientation follows the elements: reverse each quadrilateral.
    if (g.cell_shape == CellShape::quadrilateral)
      for (std::size_t c = 0; c < g.cells.size(); c += 4) std::swap(g.cells[c + 1], g.cells[c + 3]);
    flipped.add_group(std::move(g));
  }
  mesh = std::move(flipped);
}

Vec3 unit_direction(double angle)
{
  return Vec3(std::cos(angle), std::sin(angle), 0.0);
}

/// Leaflet k's mid-surface P(u, s) (see the header).
class LeafletSurface {
 public:
  LeafletSurface(const ValveMeshParameters& p, int k) : p_(p)
  {
    centre_angle_ = p.first_leaflet_angle * pi / 180.0 + 2.0 * pi * k / 3.0;
    offset_ = 0.5 * p.free_edge_gap;
    attachment_radius_ = p.tube_radius;
    // The commissure lies on the wall, `offset_` from the coaptation line at +-60 degrees.
    half_angle_ = pi / 3.0 - std::asin(offset_ / attachment_radius_);
  }

  Vec3 attachment(double u) const
  {
    const Vec3 on_wall = attachment_radius_ * unit_direction(centre_angle_ + u * half_angle_);
    return on_wall + Vec3(0, 0, p_.valve_base + (p_.commissure_height - p_.commissure_strip) * u * u);
  }

  Vec3 free_edge(double u) const
  {
    // The two segments meet at the centre point C0, on the leaflet's bisector where both offset lines cross.
    const Vec3 centre = offset_ / std::sin(pi / 3.0) * unit_direction(centre_angle_);
    const double side = u < 0 ? -1.0 : 1.0;
    const Vec3 commissure = attachment_radius_ * unit_direction(centre_angle_ + side * half_angle_);
    const Vec3 point = centre + std::abs(u) * (commissure - centre);
    return point + Vec3(0, 0, p_.valve_base + p_.commissure_height - p_.free_edge_drop * (1.0 - std::abs(u)));
  }

  Vec3 point(double u, double s) const
  {
    return (1.0 - s) * attachment(u) + s * free_edge(u) -
           Vec3(0, 0, p_.sag * std::sin(pi * s) * (1.0 - u * u));
  }

  /// Unit normal of the mid-surface (central differences in the parameters).
  Vec3 normal(double u, double s) const
  {
    const double d = 1e-6;
    const Vec3 du = point(std::min(u + d, 1.0), s) - point(std::max(u - d, -1.0), s);
    const Vec3 ds = point(u, std::min(s + d, 1.0)) - point(u, std::max(s - d, 0.0));
    return du.cross(ds).normalized();
  }

 private:
  const ValveMeshParameters& p_;
  double centre_angle_ = 0, offset_ = 0, attachment_radius_ = 0, half_angle_ = 0;
};

Mesh leaflet_mesh(const ValveMeshParameters& p, int k)
{
  // A unit block (x: across, y: attachment -> free edge, z: through the thickness) with its groups,
  // selected in parameter space, then mapped onto the leaflet.
  Mesh block = box_mesh(CellShape::hexahedron, Vec3::Zero(), Vec3::Ones(),
                        {p.leaflet_across, p.leaflet_radial, p.leaflet_through});
  const double tol = 1e-9;
  block.add_boundary_group("attachment",
                           [&](const Vec3& c) { return c[1] < tol || c[0] < tol || c[0] > 1 - tol; });
  block.add_boundary_group("tau1", [&](const Vec3& c) { return (c[1] < tol && c[0] < 0.5) || c[0] < tol; });
  block.add_boundary_group("tau2",
                           [&](const Vec3& c) { return (c[1] < tol && c[0] > 0.5) || c[0] > 1 - tol; });
  block.add_boundary_group("free_edge", [&](const Vec3& c) { return c[1] > 1 - tol; });
  block.add_boundary_group("commissure1", [&](const Vec3& c) { return c[0] < tol; });
  block.add_boundary_group("commissure2", [&](const Vec3& c) { return c[0] > 1 - tol; });
  std::vector<int> end1, end2;
  for (std::size_t n = 0; n < block.num_nodes(); ++n) {
    const Vec3& x = block.nodes()[n];
    if (x[1] > 1 - tol && x[0] < tol) end1.push_back(static_cast<int>(n));
    if (x[1] > 1 - tol && x[0] > 1 - tol) end2.push_back(static_cast<int>(n));
  }
  block.add_point_group("n1", end1);
  block.add_point_group("n2", end2);

  const LeafletSurface surface(p, k);
  for (Vec3& x : block.nodes()) {
    const double u = 2.0 * x[0] - 1.0, s = x[1], through = x[2] - 0.5;
    x = surface.point(u, s) + through * p.leaflet_thickness * surface.normal(u, s);
  }
  orient_positively(block);
  return block;
}

Mesh tube_mesh(const ValveMeshParameters& p)
{
  Mesh block = box_mesh(CellShape::hexahedron, Vec3::Zero(), Vec3::Ones(),
                        {p.tube_through, p.tube_around, p.tube_along});
  // Close the ring: the last layer of nodes around (y = 1) is the first (y = 0).
  const int nx = p.tube_through + 1, ny = p.tube_around + 1;
  auto index_of = [&](int i, int j, int k) { return i + nx * (j + ny * k); };
  std::vector<int> connectivity = block.connectivity();
  for (int& n : connectivity) {
    const int i = n % nx, j = (n / nx) % ny, k = n / (nx * ny);
    if (j == p.tube_around) n = index_of(i, 0, k);
  }
  std::vector<Vec3> nodes = block.nodes();
  for (Vec3& x : nodes) {
    const double r = p.tube_radius + x[0] * p.tube_wall, theta = 2.0 * pi * x[1];
    x = Vec3(r * std::cos(theta), r * std::sin(theta), x[2] * p.tube_length);
  }
  std::vector<PhysicalGroup> kept;
  for (const PhysicalGroup& g : block.groups()) {
    PhysicalGroup renamed = g;
    if (g.name == "body")
      renamed.name = "tube";
    else if (g.name == "xmin")
      renamed.name = "tube_inner";
    else if (g.name == "xmax")
      renamed.name = "tube_outer";
    else if (g.name == "zmin")
      renamed.name = "tube_inlet";
    else if (g.name == "zmax")
      renamed.name = "tube_outlet";
    else
      continue; // the seam (ymin, ymax) and corner points are not surfaces of the ring
    for (int& n : renamed.cells) {
      const int i = n % nx, j = (n / nx) % ny, k = n / (nx * ny);
      if (j == p.tube_around) n = index_of(i, 0, k);
    }
    renamed.nodes.clear();
    kept.push_back(std::move(renamed));
  }
  // Drop the seam's duplicate nodes by renumbering the nodes that are used.
  std::vector<int> new_index(nodes.size(), -1);
  std::vector<Vec3> used_nodes;
  auto renumber = [&](int& n) {
    if (new_index[n] < 0) {
      new_index[n] = static_cast<int>(used_nodes.size());
      used_nodes.push_back(nodes[n]);
    }
    n = new_index[n];
  };
  for (int& n : connectivity) renumber(n);
  Mesh ring(CellShape::hexahedron, std::move(used_nodes), std::move(connectivity));
  for (PhysicalGroup& g : kept) {
    for (int& n : g.cells) n = new_index[n];
    ring.add_group(std::move(g));
  }
  orient_positively(ring);
  return ring;
}

} // namespace

void check(const ValveMeshParameters& p)
{
  auto positive = [](double value, const char* name) {
    if (!(value > 0)) throw std::invalid_argument(std::string(name) + " must be positive");
  };
  positive(p.tube_radius, "tube radius");
  positive(p.tube_wall, "tube wall");
  positive(p.tube_length, "tube length");
  positive(p.leaflet_thickness, "leaflet thickness");
  positive(p.commissure_height, "commissure height");
  positive(p.commissure_strip, "commissure strip");
  if (p.sag < 0) throw std::invalid_argument("sag must be >= 0");
  if (p.free_edge_drop < 0 || p.free_edge_drop >= p.commissure_height)
    throw std::invalid_argument("free-edge drop must be >= 0 and below the commissure height");
  if (p.free_edge_gap < 0) throw std::invalid_argument("free-edge gap must be >= 0");
  if (p.commissure_strip >= p.commissure_height)
    throw std::invalid_argument("commissure strip must be below the commissure height");
  if (p.free_edge_gap + p.leaflet_thickness >= p.tube_radius)
    throw std::invalid_argument("free-edge gap plus thickness must be well below the tube radius");
  if (p.valve_base < 0 || p.valve_base + p.commissure_height > p.tube_length)
    throw std::invalid_argument("the valve (base .. base + commissure height) must lie inside the tube");
  if (p.leaflet_across < 2 || p.leaflet_across % 2 != 0)
    throw std::invalid_argument("leaflet elements across must be even and >= 2");
  if (p.leaflet_radial < 1 || p.leaflet_through < 1 || p.tube_through < 1 || p.tube_along < 1)
    throw std::invalid_argument("element counts must be >= 1");
  if (p.tube_around < 3) throw std::invalid_argument("tube elements around must be >= 3");
}

Mesh aortic_valve_mesh(const ValveMeshParameters& p)
{
  check(p);
  Mesh mesh(CellShape::hexahedron, {}, {});
  for (int k = 0; k < 3; ++k) {
    const std::string name = fmt::format("leaflet{}", k + 1);
    append(mesh, leaflet_mesh(p, k), [&](const std::string& g) {
      if (g == "body") return name;
      if (g == "attachment" || g == "tau1" || g == "tau2" || g == "free_edge" || g == "n1" || g == "n2" ||
          g == "commissure1" || g == "commissure2")
        return name + "_" + g;
      return std::string{};
    });
  }
  if (p.include_tube) append(mesh, tube_mesh(p), [](const std::string& g) { return g; });
  return mesh;
}

} // namespace ibvalve::fe
