#pragma once
// Rule-based fiber fields from Laplace problems on an FE mesh (Bayer et al. 2012; docs/reference.md,
// "Fiber architectures"):
//   Laplace(u) = 0 in the body, u = value on Dirichlet node sets, du/dn = 0 on the rest of the
//   boundary; the fiber direction is f0 = grad u / |grad u|.
// Linear / trilinear elements, the stiffness K_ab = int grad N_a . grad N_b dX assembled in a PETSc
// matrix (element ranges split over the ranks), Dirichlet rows and columns eliminated symmetrically,
// solved by CG with BoomerAMG (hypre) by default; options prefix "fibers_" (-fibers_ksp_type,
// -fibers_pc_type gamg ...).
#include <span>
#include <string>
#include <vector>

#include <mpi.h>

#include "fe/mesh.hpp"
#include "fe/quadrature_data.hpp"

namespace ibvalve::fibers {

using fe::Vec3;

struct DirichletSet {
  std::vector<int> nodes;
  double value = 0.0;
};

struct LaplaceOptions {
  std::string prefix = "fibers_";
  double relative_tolerance = 1e-12;
};

/// The nodal solution u (replicated). InputError when no Dirichlet node is given or a set is empty.
std::vector<double> solve_laplace(const fe::Mesh& mesh, const std::vector<DirichletSet>& conditions,
                                  MPI_Comm comm, const LaplaceOptions& options = {});

/// grad u / |grad u| at every quadrature point (element-major, points_per_element per element);
/// zero where grad u vanishes.
std::vector<Vec3> directions_at_points(const fe::Mesh& mesh, const fe::QuadratureData& quadrature,
                                       std::span<const double> u);

/// One direction per element: the element's volume-weighted mean of grad u, normalised.
std::vector<Vec3> directions_per_element(const fe::Mesh& mesh, const fe::QuadratureData& quadrature,
                                         std::span<const double> u);

// ---- Node selectors (Dirichlet data) ----

/// Nodes of a named physical group (any dimension).
std::vector<int> nodes_of_group(const fe::Mesh& mesh, const std::string& group);
/// The node nearest to `point`.
int nearest_node(const fe::Mesh& mesh, const Vec3& point);
/// Boundary nodes within `tolerance` of the plane through `point` with normal `normal`.
std::vector<int> boundary_nodes_on_plane(const fe::Mesh& mesh, const Vec3& point, const Vec3& normal,
                                         double tolerance);
/// A selector written as text: "GROUP" (a physical group), "point:x,y,z" (the nearest node) or
/// "plane:px,py,pz,nx,ny,nz" (boundary nodes on that plane, within 1e-3 of the shortest edge).
/// InputError naming the selector when it matches no node or cannot be parsed.
std::vector<int> select_nodes(const fe::Mesh& mesh, const std::string& selector);

} // namespace ibvalve::fibers
