#include "fe/mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <stdexcept>

#include "base/errors.hpp"

namespace ibvalve::fe {

namespace {

void sort_unique(std::vector<int>& v)
{
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

} // namespace

Mesh::Mesh(CellShape shape, std::vector<Vec3> nodes, std::vector<int> connectivity)
    : shape_(shape), nodes_per_element_(nodes_per_cell(shape)), nodes_(std::move(nodes)),
      connectivity_(std::move(connectivity))
{
  if (element_type(shape).dimension() != 3) throw std::invalid_argument("Mesh: cells must be 3-D");
  if (connectivity_.size() % nodes_per_element_ != 0)
    throw std::invalid_argument("Mesh: connectivity is not a whole number of elements");
  for (int n : connectivity_)
    if (n < 0 || static_cast<std::size_t>(n) >= nodes_.size())
      throw std::invalid_argument("Mesh: connectivity refers to a node that does not exist");
}

bool Mesh::has_group(const std::string& name) const
{
  return std::any_of(groups_.begin(), groups_.end(), [&](const PhysicalGroup& g) { return g.name == name; });
}

const PhysicalGroup& Mesh::group(const std::string& name) const
{
  for (const auto& g : groups_)
    if (g.name == name) return g;
  std::string names;
  for (const auto& g : groups_) names += (names.empty() ? "" : ", ") + g.name;
  throw InputError("mesh: no physical group named '" + name +
                   "' (groups: " + (names.empty() ? "none" : names) + ")");
}

void Mesh::add_group(PhysicalGroup group)
{
  group.nodes.clear();
  if (group.dimension == 3) {
    sort_unique(group.elements);
    for (int e : group.elements)
      for (int n : element(e)) group.nodes.push_back(n);
  } else {
    group.nodes = group.cells;
  }
  sort_unique(group.nodes);
  std::erase_if(groups_, [&](const PhysicalGroup& g) { return g.name == group.name; });
  groups_.push_back(std::move(group));
}

void Mesh::add_volume_group(const std::string& name, std::vector<int> elements)
{
  PhysicalGroup g;
  g.name = name;
  g.dimension = 3;
  g.elements = std::move(elements);
  add_group(std::move(g));
}

void Mesh::add_point_group(const std::string& name, std::vector<int> nodes)
{
  PhysicalGroup g;
  g.name = name;
  g.dimension = 0;
  g.cell_shape = CellShape::point;
  g.cells = std::move(nodes);
  add_group(std::move(g));
}

std::vector<std::vector<int>> Mesh::boundary_faces() const
{
  const auto local_faces = type().faces();
  std::map<std::vector<int>, std::pair<int, std::vector<int>>> seen; // sorted nodes -> (count, face)
  for (std::size_t e = 0; e < num_elements(); ++e) {
    const auto nodes = element(e);
    for (const auto& local : local_faces) {
      std::vector<int> face;
      for (int a : local) face.push_back(nodes[a]);
      std::vector<int> key = face;
      std::sort(key.begin(), key.end());
      auto [it, inserted] = seen.try_emplace(key, 0, face);
      ++it->second.first;
    }
  }
  std::vector<std::vector<int>> boundary;
  for (auto& [key, value] : seen)
    if (value.first == 1) boundary.push_back(std::move(value.second));
  return boundary;
}

void Mesh::add_boundary_group(const std::string& name, const std::function<bool(const Vec3&)>& select)
{
  PhysicalGroup g;
  g.name = name;
  g.dimension = 2;
  g.cell_shape = type().face_shape();
  for (const auto& face : boundary_faces()) {
    Vec3 centroid = Vec3::Zero();
    for (int n : face) centroid += nodes_[n];
    centroid /= static_cast<double>(face.size());
    if (select(centroid)) g.cells.insert(g.cells.end(), face.begin(), face.end());
  }
  add_group(std::move(g));
}

double Mesh::volume() const
{
  const ElementType& t = type();
  const QuadratureRule rule = t.quadrature(2);
  std::vector<Vec3> dN(t.num_nodes());
  double total = 0.0;
  for (std::size_t e = 0; e < num_elements(); ++e) {
    const auto nodes = element(e);
    for (std::size_t q = 0; q < rule.size(); ++q) {
      t.gradients(rule.points[q], dN);
      Eigen::Matrix3d jacobian = Eigen::Matrix3d::Zero();
      for (int a = 0; a < t.num_nodes(); ++a) jacobian += nodes_[nodes[a]] * dN[a].transpose();
      total += jacobian.determinant() * rule.weights[q];
    }
  }
  return total;
}

std::pair<double, double> Mesh::edge_length_range() const
{
  double lo = INFINITY, hi = 0.0;
  for (std::size_t e = 0; e < num_elements(); ++e) {
    const auto nodes = element(e);
    for (const auto& face : type().faces())
      for (std::size_t i = 0; i < face.size(); ++i) {
        const double length = (nodes_[nodes[face[i]]] - nodes_[nodes[face[(i + 1) % face.size()]]]).norm();
        lo = std::min(lo, length);
        hi = std::max(hi, length);
      }
  }
  return {lo, hi};
}

Mesh submesh(const Mesh& mesh, const std::vector<int>& elements, std::vector<int>* node_map)
{
  std::vector<int> new_index(mesh.num_nodes(), -1);
  std::vector<int> old_index;
  std::vector<int> connectivity;
  for (int e : elements)
    for (int n : mesh.element(e)) {
      if (new_index[n] < 0) {
        new_index[n] = static_cast<int>(old_index.size());
        old_index.push_back(n);
      }
      connectivity.push_back(new_index[n]);
    }
  std::vector<Vec3> nodes;
  for (int n : old_index) nodes.push_back(mesh.nodes()[n]);
  Mesh part(mesh.shape(), std::move(nodes), std::move(connectivity));

  std::vector<int> new_element(mesh.num_elements(), -1);
  for (std::size_t i = 0; i < elements.size(); ++i) new_element[elements[i]] = static_cast<int>(i);
  for (const auto& g : mesh.groups()) {
    PhysicalGroup kept;
    kept.name = g.name;
    kept.dimension = g.dimension;
    kept.tag = g.tag;
    kept.cell_shape = g.cell_shape;
    if (g.dimension == 3) {
      for (int e : g.elements)
        if (new_element[e] >= 0) kept.elements.push_back(new_element[e]);
      if (kept.elements.empty()) continue;
    } else {
      const int k = nodes_per_cell(g.cell_shape);
      for (std::size_t c = 0; c + k <= g.cells.size(); c += k) {
        bool inside = true;
        for (int i = 0; i < k; ++i) inside = inside && new_index[g.cells[c + i]] >= 0;
        if (!inside) continue;
        for (int i = 0; i < k; ++i) kept.cells.push_back(new_index[g.cells[c + i]]);
      }
      if (kept.cells.empty()) continue;
    }
    part.add_group(std::move(kept));
  }
  if (node_map) *node_map = std::move(old_index);
  return part;
}

Mesh box_mesh(CellShape shape, const Vec3& lo, const Vec3& hi, std::array<int, 3> n)
{
  if (shape != CellShape::hexahedron && shape != CellShape::tetrahedron)
    throw std::invalid_argument("box_mesh: hexahedra or tetrahedra");
  auto node_index = [&](int i, int j, int k) { return i + (n[0] + 1) * (j + (n[1] + 1) * k); };
  std::vector<Vec3> nodes;
  for (int k = 0; k <= n[2]; ++k)
    for (int j = 0; j <= n[1]; ++j)
      for (int i = 0; i <= n[0]; ++i)
        nodes.push_back(lo +
                        Vec3(double(i) / n[0], double(j) / n[1], double(k) / n[2]).cwiseProduct(hi - lo));
  std::vector<int> connectivity;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        // Corner c = bits (x, y, z).
        auto corner = [&](int c) { return node_index(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1)); };
        if (shape == CellShape::hexahedron) {
          for (int c : {0, 1, 3, 2, 4, 5, 7, 6}) connectivity.push_back(corner(c));
        } else {
          // Kuhn: one tetrahedron per ordering of the axes, along the diagonal from corner 0 to corner 7.
          const std::array<std::array<int, 3>, 6> orders{
              {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
          for (const auto& order : orders) {
            std::array<int, 4> tet{0, 1 << order[0], (1 << order[0]) | (1 << order[1]), 7};
            std::array<int, 4> ids;
            for (int v = 0; v < 4; ++v) ids[v] = corner(tet[v]);
            const Vec3 a = nodes[ids[1]] - nodes[ids[0]], b = nodes[ids[2]] - nodes[ids[0]],
                       c = nodes[ids[3]] - nodes[ids[0]];
            if (a.cross(b).dot(c) < 0) std::swap(ids[1], ids[2]);
            connectivity.insert(connectivity.end(), ids.begin(), ids.end());
          }
        }
      }
  Mesh mesh(shape, std::move(nodes), std::move(connectivity));
  std::vector<int> all(mesh.num_elements());
  for (std::size_t e = 0; e < all.size(); ++e) all[e] = static_cast<int>(e);
  mesh.add_volume_group("body", std::move(all));
  const double tolerance = 1e-9 * (hi - lo).norm();
  const char* names[3][2] = {{"xmin", "xmax"}, {"ymin", "ymax"}, {"zmin", "zmax"}};
  for (int d = 0; d < 3; ++d) {
    mesh.add_boundary_group(names[d][0], [&](const Vec3& x) { return std::abs(x[d] - lo[d]) < tolerance; });
    mesh.add_boundary_group(names[d][1], [&](const Vec3& x) { return std::abs(x[d] - hi[d]) < tolerance; });
  }
  mesh.add_point_group("corner_lo", {node_index(0, 0, 0)});
  mesh.add_point_group("corner_hi", {node_index(n[0], n[1], n[2])});
  return mesh;
}

Mesh annular_sector_mesh(CellShape shape, double r_inner, double r_outer, double angle, double height,
                         std::array<int, 3> n)
{
  Mesh box = box_mesh(shape, Vec3(r_inner, 0, 0), Vec3(r_outer, angle, height), n);
  // Map (r, theta, z) to (r cos theta, r sin theta, z); the map keeps orientation (its Jacobian is r > 0).
  for (Vec3& x : box.nodes()) x = Vec3(x[0] * std::cos(x[1]), x[0] * std::sin(x[1]), x[2]);
  Mesh mesh(shape, box.nodes(), box.connectivity());
  const std::map<std::string, std::string> renamed{{"body", "body"},   {"xmin", "inner"},  {"xmax", "outer"},
                                                   {"ymin", "theta0"}, {"ymax", "theta1"}, {"zmin", "bottom"},
                                                   {"zmax", "top"}};
  for (PhysicalGroup g : box.groups()) {
    auto it = renamed.find(g.name);
    if (it == renamed.end()) continue;
    g.name = it->second;
    mesh.add_group(std::move(g));
  }
  return mesh;
}

void perturb_interior_nodes(Mesh& mesh, double fraction, unsigned seed)
{
  std::vector<char> on_boundary(mesh.num_nodes(), 0);
  for (const auto& face : mesh.boundary_faces())
    for (int n : face) on_boundary[n] = 1;
  const double h = mesh.edge_length_range().first;
  std::mt19937 generator(seed);
  std::uniform_real_distribution<double> uniform(-fraction * h, fraction * h);
  for (std::size_t n = 0; n < mesh.num_nodes(); ++n)
    if (!on_boundary[n]) mesh.nodes()[n] += Vec3(uniform(generator), uniform(generator), uniform(generator));
}

} // namespace ibvalve::fe
