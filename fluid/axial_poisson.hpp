#pragma once
// Exact solve of the pressure Poisson operator K when the blocked cells (fluid/solid_cells.hpp) are
// the same in every z-plane, as for a straight tube along z held as a wall. K on the fluid cells is
// then a Kronecker sum, K = I_xy (x) T_z + L_xy (x) I_z: T_z the 1-D second difference along z with its
// end closures, L_xy the operator of one plane's fluid cells, closed at the staircase by the blocked
// faces (no flux). The eigenvectors of T_z (symmetric tridiagonal) decouple the z-planes into nz 2-D
// problems (L_xy + lambda_k I) q_k = b_k, each factored once by sparse Cholesky: the method of
// Buzbee, Golub & Nielson (1970, SIAM J. Numer. Anal. 7:627) with a direct solve across the plane
// in place of the second transform.
//
// Nothing is assumed of K's entries: they are read from the assembled matrix, the separation is
// checked on every fluid row (each z and each in-plane coupling the same in every plane and
// column, each diagonal the sum of a column's and a plane's part), and make() returns nullptr
// where it does not hold, so that the caller keeps its algebraic multigrid. Every rank holds the
// whole operator and solves the whole problem (the right side gathered once a solve): cheap next
// to a multigrid cycle for the grids this serves (a 2-D factor per plane of a cross-section).
#include <memory>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <petscmat.h>

#include "fluid/grid.hpp"
#include "io/petsc_handle.hpp"

namespace ibvalve::fluid {

class AxialPoisson {
 public:
  /// K on the pressure sub-vector `is_p` of `grid`'s global vector. Collective; nullptr (on every
  /// rank) when K does not separate along z or a plane's problem is singular.
  static std::unique_ptr<AxialPoisson> make(const StaggeredGrid& grid, Mat K, IS is_p);

  /// phi = K^-1 r (vectors of K's layout). Collective.
  void solve(Vec r, Vec phi) const;

  /// Fluid cells of one plane and the planes.
  PetscInt plane_cells() const { return static_cast<PetscInt>(plane_of_.size()); }
  PetscInt planes() const { return static_cast<PetscInt>(eigenvalues_.size()); }

 private:
  using Factor = Eigen::SimplicialLLT<Eigen::SparseMatrix<double>>;
  AxialPoisson() = default;
  /// Where each of K's rows sits in the solve (row_of: cell -> K's row; diagonal: K's by row).
  void place_rows(Mat K, const std::vector<PetscInt>& row_of, const std::vector<double>& diagonal);

  petsc::OwnedVecScatter to_all_;     // K's layout -> every entry on every rank
  petsc::OwnedVec all_;               // the gathered right side
  std::vector<PetscInt> fluid_row_;   // [k * nf + m]: K's global row of plane k's fluid cell m
  std::vector<PetscInt> plane_of_;    // fluid cell m of a plane: i + nx j
  std::vector<PetscInt> blocked_row_; // K's global rows of blocked cells (identity rows)
  std::vector<double> blocked_diagonal_;
  PetscInt owned_begin_ = 0, owned_end_ = 0;
  std::vector<PetscInt> owned_slot_; // owned row - owned_begin_ -> index into the solution (or -1: blocked)
  Eigen::MatrixXd modes_;            // eigenvectors of T_z (columns)
  Eigen::VectorXd eigenvalues_;
  std::vector<std::unique_ptr<Factor>> factors_; // of L_xy + lambda_k I, one a plane
  mutable Eigen::MatrixXd work_, coefficients_;  // nz x nf
};

} // namespace ibvalve::fluid
