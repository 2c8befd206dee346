#pragma once
// A finite-element mesh of one cell type (trilinear hexahedra or linear tetrahedra) with named
// physical groups, as Gmsh defines them: a volume group is a set of the mesh's elements (a body part
// such as a leaflet or the tube); a surface, curve or point group is a set of boundary cells
// (faces, edges, points) with its node set (attachment surfaces, tethered surfaces, fiber end points).
//
// The structure mesh is small next to the fluid grid, so every rank holds it whole (docs/fe.md).
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "fe/element.hpp"

namespace ibvalve::fe {

struct PhysicalGroup {
  std::string name;
  int dimension = 3; ///< 3: volume, 2: surface, 1: curve, 0: points
  int tag = -1;      ///< Gmsh physical tag (assigned on write when -1)
  /// Volume groups: indices into the mesh's elements.
  std::vector<int> elements;
  /// Lower-dimensional groups: cells of shape `cell_shape`, node indices flat.
  CellShape cell_shape = CellShape::point;
  std::vector<int> cells;
  /// Every node of the group, sorted and unique.
  std::vector<int> nodes;
};

class Mesh {
 public:
  Mesh() = default;
  Mesh(CellShape shape, std::vector<Vec3> nodes, std::vector<int> connectivity);

  CellShape shape() const { return shape_; }
  const ElementType& type() const { return element_type(shape_); }
  int nodes_per_element() const { return nodes_per_element_; }
  std::size_t num_nodes() const { return nodes_.size(); }
  std::size_t num_elements() const { return connectivity_.size() / nodes_per_element_; }
  const std::vector<Vec3>& nodes() const { return nodes_; }
  std::vector<Vec3>& nodes() { return nodes_; }
  std::span<const int> element(std::size_t e) const
  {
    return {connectivity_.data() + e * nodes_per_element_, static_cast<std::size_t>(nodes_per_element_)};
  }
  const std::vector<int>& connectivity() const { return connectivity_; }

  const std::vector<PhysicalGroup>& groups() const { return groups_; }
  bool has_group(const std::string& name) const;
  /// The group called `name`; InputError listing the groups there are when it is missing.
  const PhysicalGroup& group(const std::string& name) const;
  /// Adds (or replaces) a group; fills its node set from its cells or elements.
  void add_group(PhysicalGroup group);
  /// A volume group of elements.
  void add_volume_group(const std::string& name, std::vector<int> elements);
  /// A point group of nodes.
  void add_point_group(const std::string& name, std::vector<int> nodes);
  /// A surface group of the boundary faces whose centroid satisfies `select`.
  void add_boundary_group(const std::string& name, const std::function<bool(const Vec3& centroid)>& select);

  /// Boundary faces (faces of exactly one element), as node lists in the element's outward order.
  std::vector<std::vector<int>> boundary_faces() const;
  /// Element volumes summed (the reference volume of the body).
  double volume() const;
  /// Smallest and largest edge length over the elements (for selectors' tolerances and reports).
  std::pair<double, double> edge_length_range() const;

 private:
  CellShape shape_ = CellShape::hexahedron;
  int nodes_per_element_ = 8;
  std::vector<Vec3> nodes_;
  std::vector<int> connectivity_;
  std::vector<PhysicalGroup> groups_;
};

/// The mesh made of `elements` of `mesh` (nodes renumbered in order of first use); groups are kept
/// where they meet the part (volume groups restricted, lower groups to the cells whose nodes are all in
/// it). `node_map`, when given, receives the original index of every new node.
Mesh submesh(const Mesh& mesh, const std::vector<int>& elements, std::vector<int>* node_map = nullptr);

// ---- Generated meshes (tests, examples) ----

/// A box [lo, hi] split into n[0] x n[1] x n[2] hexahedra, or into 6 tetrahedra per hexahedron
/// (Kuhn's subdivision: every cell's main diagonal the same way, so faces match). Groups: volume
/// "body"; surfaces "xmin", "xmax", "ymin", "ymax", "zmin", "zmax"; points "corner_lo", "corner_hi".
Mesh box_mesh(CellShape shape, const Vec3& lo, const Vec3& hi, std::array<int, 3> n);

/// An annular sector r in [r_inner, r_outer], theta in [0, angle] (radians, about the z axis),
/// z in [0, height], with n = (n_r, n_theta, n_z) cells. Groups: volume "body"; surfaces "inner",
/// "outer", "theta0", "theta1", "bottom", "top".
Mesh annular_sector_mesh(CellShape shape, double r_inner, double r_outer, double angle, double height,
                         std::array<int, 3> n);

/// Moves every node off the mesh boundary by a random amount up to `fraction` of the smallest edge
/// in each direction (fixed seed): distorted meshes for patch tests.
void perturb_interior_nodes(Mesh& mesh, double fraction, unsigned seed = 7);

} // namespace ibvalve::fe
