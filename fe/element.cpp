#include "fe/element.hpp"

#include <array>
#include <fmt/format.h>
#include <stdexcept>

namespace ibvalve::fe {

namespace {

// Trilinear hexahedron on [-1, 1]^3; corners in Gmsh order (bottom face z = -1 counter-clockwise, then top).
class Hex8 final : public ElementType {
 public:
  CellShape shape() const override { return CellShape::hexahedron; }
  std::string name() const override { return "hex8"; }
  int dimension() const override { return 3; }
  int num_nodes() const override { return 8; }
  void values(const Vec3& xi, std::span<double> N) const override
  {
    for (int a = 0; a < 8; ++a)
      N[a] = 0.125 * (1 + corner[a][0] * xi[0]) * (1 + corner[a][1] * xi[1]) * (1 + corner[a][2] * xi[2]);
  }
  void gradients(const Vec3& xi, std::span<Vec3> dN) const override
  {
    for (int a = 0; a < 8; ++a) {
      const double sx = 1 + corner[a][0] * xi[0], sy = 1 + corner[a][1] * xi[1],
                   sz = 1 + corner[a][2] * xi[2];
      dN[a] = 0.125 * Vec3(corner[a][0] * sy * sz, corner[a][1] * sx * sz, corner[a][2] * sx * sy);
    }
  }
  QuadratureRule quadrature(int degree) const override { return hexahedron_rule(degree); }
  std::vector<std::vector<int>> faces() const override
  {
    return {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  }
  CellShape face_shape() const override { return CellShape::quadrilateral; }
  std::vector<Vec3> reference_nodes() const override
  {
    std::vector<Vec3> nodes;
    for (const auto& c : corner) nodes.emplace_back(c[0], c[1], c[2]);
    return nodes;
  }

 private:
  static constexpr std::array<std::array<double, 3>, 8> corner{
      {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1}, {-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}}};
};

// Linear tetrahedron: N = (1 - xi - eta - zeta, xi, eta, zeta).
class Tet4 final : public ElementType {
 public:
  CellShape shape() const override { return CellShape::tetrahedron; }
  std::string name() const override { return "tet4"; }
  int dimension() const override { return 3; }
  int num_nodes() const override { return 4; }
  void values(const Vec3& xi, std::span<double> N) const override
  {
    N[0] = 1 - xi[0] - xi[1] - xi[2];
    N[1] = xi[0];
    N[2] = xi[1];
    N[3] = xi[2];
  }
  void gradients(const Vec3&, std::span<Vec3> dN) const override
  {
    dN[0] = Vec3(-1, -1, -1);
    dN[1] = Vec3(1, 0, 0);
    dN[2] = Vec3(0, 1, 0);
    dN[3] = Vec3(0, 0, 1);
  }
  QuadratureRule quadrature(int degree) const override { return tetrahedron_rule(degree); }
  std::vector<std::vector<int>> faces() const override
  {
    return {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  }
  CellShape face_shape() const override { return CellShape::triangle; }
  std::vector<Vec3> reference_nodes() const override
  {
    return {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  }
};

// Bilinear quadrilateral on [-1, 1]^2 (faces of hexahedra, surface loads).
class Quad4 final : public ElementType {
 public:
  CellShape shape() const override { return CellShape::quadrilateral; }
  std::string name() const override { return "quad4"; }
  int dimension() const override { return 2; }
  int num_nodes() const override { return 4; }
  void values(const Vec3& xi, std::span<double> N) const override
  {
    for (int a = 0; a < 4; ++a) N[a] = 0.25 * (1 + corner[a][0] * xi[0]) * (1 + corner[a][1] * xi[1]);
  }
  void gradients(const Vec3& xi, std::span<Vec3> dN) const override
  {
    for (int a = 0; a < 4; ++a)
      dN[a] = 0.25 *
              Vec3(corner[a][0] * (1 + corner[a][1] * xi[1]), corner[a][1] * (1 + corner[a][0] * xi[0]), 0);
  }
  QuadratureRule quadrature(int degree) const override { return quadrilateral_rule(degree); }
  std::vector<std::vector<int>> faces() const override { return {{0, 1}, {1, 2}, {2, 3}, {3, 0}}; }
  CellShape face_shape() const override { return CellShape::line; }
  std::vector<Vec3> reference_nodes() const override
  {
    return {Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(1, 1, 0), Vec3(-1, 1, 0)};
  }

 private:
  static constexpr std::array<std::array<double, 2>, 4> corner{{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}};
};

// Linear triangle (faces of tetrahedra).
class Tri3 final : public ElementType {
 public:
  CellShape shape() const override { return CellShape::triangle; }
  std::string name() const override { return "tri3"; }
  int dimension() const override { return 2; }
  int num_nodes() const override { return 3; }
  void values(const Vec3& xi, std::span<double> N) const override
  {
    N[0] = 1 - xi[0] - xi[1];
    N[1] = xi[0];
    N[2] = xi[1];
  }
  void gradients(const Vec3&, std::span<Vec3> dN) const override
  {
    dN[0] = Vec3(-1, -1, 0);
    dN[1] = Vec3(1, 0, 0);
    dN[2] = Vec3(0, 1, 0);
  }
  QuadratureRule quadrature(int degree) const override { return triangle_rule(degree); }
  std::vector<std::vector<int>> faces() const override { return {{0, 1}, {1, 2}, {2, 0}}; }
  CellShape face_shape() const override { return CellShape::line; }
  std::vector<Vec3> reference_nodes() const override { return {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}; }
};

} // namespace

const ElementType& element_type(CellShape shape)
{
  static const Hex8 hex8;
  static const Tet4 tet4;
  static const Quad4 quad4;
  static const Tri3 tri3;
  switch (shape) {
  case CellShape::hexahedron:
    return hex8;
  case CellShape::tetrahedron:
    return tet4;
  case CellShape::quadrilateral:
    return quad4;
  case CellShape::triangle:
    return tri3;
  default:
    throw std::invalid_argument("element_type: no finite element for lines or points");
  }
}

namespace {

/// What a shape is to the files: nodes per cell, the Gmsh element type number (Gmsh reference manual,
/// "MSH file format": 1 line, 2 triangle, 3 quadrangle, 4 tetrahedron, 5 hexahedron, 15 point) and the
/// XDMF topology name (xdmf.org, "XDMF Model and Format": Topology).
struct ShapeFacts {
  CellShape shape;
  int nodes;
  int gmsh_type;
  const char* xdmf_topology;
};
constexpr ShapeFacts shape_facts[] = {
    {CellShape::hexahedron, 8, 5, "Hexahedron"},
    {CellShape::tetrahedron, 4, 4, "Tetrahedron"},
    {CellShape::quadrilateral, 4, 3, "Quadrilateral"},
    {CellShape::triangle, 3, 2, "Triangle"},
    {CellShape::line, 2, 1, "Polyline"},
    {CellShape::point, 1, 15, "Polyvertex"},
};

const ShapeFacts& facts_of(CellShape shape)
{
  for (const ShapeFacts& f : shape_facts)
    if (f.shape == shape) return f;
  throw std::logic_error("fe: a cell shape without an entry in shape_facts");
}

} // namespace

int ElementType::gmsh_type() const
{
  return gmsh_type_of(shape());
}

int nodes_per_cell(CellShape shape)
{
  return facts_of(shape).nodes;
}

int gmsh_type_of(CellShape shape)
{
  return facts_of(shape).gmsh_type;
}

CellShape shape_of_gmsh_type(int gmsh_type)
{
  for (const ShapeFacts& f : shape_facts)
    if (f.gmsh_type == gmsh_type) return f.shape;
  throw std::invalid_argument(
      fmt::format("Gmsh element type {} is not supported (first-order lines, triangles, "
                  "quadrangles, tetrahedra and hexahedra are)",
                  gmsh_type));
}

std::string xdmf_topology(CellShape shape)
{
  return facts_of(shape).xdmf_topology;
}

} // namespace ibvalve::fe
