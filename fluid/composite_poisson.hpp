#pragma once
// Cell-centred composite-grid operators on a GridHierarchy (docs/nested.md): gradient G on the composite
// faces, the adjoint divergence D = -V^{-1} G^T W, and the composite Laplacian (the pressure operator)
// assembled as the symmetric PETSc matrix A = G^T W G (so -D G u = f reads A u = V f - G^T W c).
//
// Composite cells: the cells of each level not covered by the next finer level, numbered level by level,
// box by box, x fastest; the rows are split over the ranks in that order (PETSc's default split).
// Composite faces, each with a gradient stencil and a weight W_f = (face area) x (normal distance):
//  - between two cells of one level: (u+ - u-)/h, W = A h;
//  - on the domain boundary: Dirichlet (g - u)/(h/2) (sign by side), W = A h/2; Neumann: no face (zero flux);
//    `mixed`: Dirichlet on the boundary faces a predicate selects (the traction sides of an open box: the
//    pressure is given there), Neumann on the others (walls);
//  - a coarse-fine face (a face of a fine cell whose neighbour is not on the fine level): the coarse value is
//    carried to the fine face's tangential position, U* = U_C + sum_t delta_t dU/dt (central coarse
//    differences, one-sided where a neighbour is missing), and G = (U* - u_f)/((h + H)/2) along the
//    normal, W = A_fine (h + H)/2 (`tangential_linear`); `two_point` leaves out the tangential term.
// Either way A is symmetric positive (semi)definite by construction and D is conservative: the sum of
// V D g over all cells is the flux of g through the domain boundary, with no loss at coarse-fine faces.
// `two_point` makes D exactly the refluxed flux divergence (the coarse flux through a coarse-fine face is
// the sum of its fine fluxes); `tangential_linear` moves a part O(h) of it to tangential neighbours.
// Why the tangential term: the two-point flux is inconsistent at hanging faces (the coarse centre is
// off the fine face's normal line by h/2), an O(1) alternating flux error; carrying U_C along the face
// leaves an O(h) smooth flux error, a dipole layer of strength O(h^2) (Ewing, Lazarov & Vassilevski
// 1991, Math. Comp. 56:437, discuss both). Measured orders are in docs/nested.md.
#include <functional>
#include <string>
#include <vector>

#include <petscksp.h>

#include "fluid/composite_cells.hpp"
#include "fluid/hierarchy.hpp"
#include "io/petsc_handle.hpp"

namespace ibvalve::fluid {

enum class CoarseFineStencil { two_point, tangential_linear };
enum class CompositeBoundary { dirichlet, neumann, mixed };
/// For CompositeBoundary::mixed: whether the boundary face centred at `x` on side `side` (side_index of
/// fluid/boundary.hpp: 2 d + upper) is a Dirichlet face.
using DirichletFaces = std::function<bool(int side, const Real3& x)>;

/// One composite face, as its enumerating rank sees it (for fluxes and tests).
struct CompositeFace {
  int normal = 0;
  int level = 0; // the finer side's level
  Real3 center{};
  double area = 0.0;
  bool on_boundary = false;
  bool coarse_fine = false;
  int side = -1;        // boundary faces: the side index 2 d + upper
  double outward = 0.0; // boundary faces: +1 / -1 when +normal points out of / into the domain;
                        // coarse-fine faces: +1 / -1 when +normal points from the fine to the coarse cell
};

class CompositeOperators {
 public:
  /// `dirichlet_value(x)`: boundary data for `dirichlet` (ignored for `neumann`; zero when empty for
  /// `mixed`). `dirichlet_faces`: the Dirichlet faces of `mixed`. Collective on `comm`.
  /// Every side of the domain is a Dirichlet or Neumann side: a periodic direction is refused
  /// (std::invalid_argument) until the numbering learns periodic images.
  CompositeOperators(MPI_Comm comm, const GridHierarchy& hierarchy, CoarseFineStencil stencil,
                     CompositeBoundary boundary, std::function<double(const Real3&)> dirichlet_value = {},
                     DirichletFaces dirichlet_faces = {});
  CompositeOperators(const CompositeOperators&) = delete;
  CompositeOperators& operator=(const CompositeOperators&) = delete;

  const CompositeCells& cells() const { return cells_; }
  MPI_Comm comm() const { return comm_; }
  /// Faces x cells: (G u)_f, without the boundary data part.
  Mat gradient() const { return gradient_.get(); }
  /// A = G^T W G, symmetric; the pressure operator (integrated over each cell, so A u = V f).
  Mat laplacian() const { return laplacian_.get(); }
  /// Face weights W (face vector) and the boundary data part c of the gradient (G u + c).
  Vec weights() const { return weights_.get(); }
  Vec boundary_part() const { return boundary_part_.get(); }
  /// Cell volumes V (cell vector).
  Vec volumes() const { return volumes_.get(); }
  /// The faces this rank owns, in the order of the face vectors' owned entries.
  const std::vector<CompositeFace>& owned_faces() const { return faces_; }
  /// Whether the boundary face of `cell` of `level` on its side `side` (2 d + upper) is a composite face
  /// (a Dirichlet face). The one place that decides it, for the face numbering of CompositeVelocity too.
  bool boundary_face(int level, const Index3& cell, int side) const;
  /// True when some boundary face is a Dirichlet face (the pressure then has no free constant).
  bool any_dirichlet() const { return any_dirichlet_; }

  /// New vectors laid out like cells / faces, zeroed.
  petsc::OwnedVec create_cell_vector() const;
  petsc::OwnedVec create_face_vector() const;
  /// The composite divergence of the face field `g` (normal components): D g = -V^{-1} G^T W g.
  void divergence(Vec g, Vec out) const;
  /// The right side V f - G^T W c of A u = V f for -div grad u = f (f at cell centres).
  void right_side(const std::function<double(const Real3&)>& f, Vec out) const;
  /// Cell-centre values of `u(x)` into a cell vector.
  void sample(const std::function<double(const Real3&)>& u, Vec out) const;
  /// The normal component of the vector field `v(x)` at each composite face centre into a face vector.
  void sample_normal(const std::function<Real3(const Real3&)>& v, Vec out) const;

 private:
  MPI_Comm comm_;
  const GridHierarchy* hierarchy_;
  CompositeCells cells_;
  petsc::OwnedMat gradient_, laplacian_;
  petsc::OwnedVec weights_, boundary_part_, volumes_;
  std::vector<CompositeFace> faces_;
  CompositeBoundary boundary_;
  DirichletFaces dirichlet_faces_;
  bool any_dirichlet_ = false;
};

/// Conjugate gradients preconditioned by hypre BoomerAMG on the assembled composite matrix. Options
/// prefix `prefix` (default settings: -<prefix>ksp_type cg -<prefix>pc_type hypre, rtol 1e-10 on the
/// unpreconditioned residual).
/// With Neumann boundaries the constant null space is removed.
class CompositePoissonSolver {
 public:
  CompositePoissonSolver(const CompositeOperators& operators, bool singular, const std::string& prefix,
                         double rtol = 1e-10);
  CompositePoissonSolver(const CompositePoissonSolver&) = delete;
  CompositePoissonSolver& operator=(const CompositePoissonSolver&) = delete;
  /// Solves A x = b; returns the iteration count. Throws RunError when the solver diverges.
  PetscInt solve(Vec b, Vec x) const;

 private:
  petsc::OwnedKSP ksp_;
  petsc::OwnedMatNullSpace null_space_;
};

} // namespace ibvalve::fluid
