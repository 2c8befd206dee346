#pragma once
// Lagrange element types behind one interface: shape functions and their reference gradients on the
// reference cell, the reference quadrature, and the cell's faces. Linear and trilinear cells now;
// quadratic ones are new subclasses (docs/fe.md).
//
// Node orderings are Gmsh's (which are also VTK's and XDMF's for these cells), so connectivity read
// with the gmsh API goes to ParaView unchanged.
#include <span>
#include <string>
#include <vector>

#include "fe/quadrature.hpp"

namespace ibvalve::fe {

enum class CellShape { hexahedron, tetrahedron, quadrilateral, triangle, line, point };

class ElementType {
 public:
  virtual ~ElementType() = default;
  virtual CellShape shape() const = 0;
  virtual std::string name() const = 0;
  virtual int dimension() const = 0;
  virtual int num_nodes() const = 0;
  /// N_a(xi), a = 0 .. num_nodes()-1.
  virtual void values(const Vec3& xi, std::span<double> N) const = 0;
  /// dN_a/dxi (unused reference directions are zero).
  virtual void gradients(const Vec3& xi, std::span<Vec3> dN) const = 0;
  /// A rule exact for polynomials of degree <= `degree` on the reference cell.
  virtual QuadratureRule quadrature(int degree) const = 0;
  /// Local node lists of the faces (outward orientation), for boundary extraction.
  virtual std::vector<std::vector<int>> faces() const = 0;
  /// The shape of those faces.
  virtual CellShape face_shape() const = 0;
  /// Gmsh element type number of its shape (gmsh_type_of).
  int gmsh_type() const;
  /// Reference coordinates of the nodes.
  virtual std::vector<Vec3> reference_nodes() const = 0;
};

/// The element type of a shape (linear / multilinear Lagrange); throws for `line` and `point`.
const ElementType& element_type(CellShape shape);
/// Nodes per cell of a shape (1 for a point, 2 for a line ...).
int nodes_per_cell(CellShape shape);
/// Gmsh element type number of a shape.
int gmsh_type_of(CellShape shape);
/// The shape of a Gmsh element type number (first-order types only); throws for others.
CellShape shape_of_gmsh_type(int gmsh_type);
/// "Hexahedron", "Tetrahedron", "Quadrilateral", "Triangle", "Polyline", "Polyvertex" (XDMF names).
std::string xdmf_topology(CellShape shape);

} // namespace ibvalve::fe
