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
// where it does not hold, so that the caller keeps its algebraic multigrid. The ranks share the
// modes: each gathers the whole right side, transforms it into its own modes, solves their planes,
// and after one all-gather of the modes' solutions transforms back only the cells it owns, so that
// the transforms' and the factors' work and memory divide among the ranks.
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
  /// The modes this rank factors and solves: [first, first + count).
  PetscInt first_mode() const { return mode_begin_; }
  PetscInt mode_count() const { return mode_end_ - mode_begin_; }

 private:
  using Factor = Eigen::SimplicialLLT<Eigen::SparseMatrix<double>>;
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  AxialPoisson() = default;
  /// Where each of K's rows sits in the solve (row_of: cell -> K's row; diagonal: K's by row).
  void place_rows(Mat K, const std::vector<PetscInt>& row_of, const std::vector<double>& diagonal);
  /// This rank's share of the modes and the all-gather's counts (modes split evenly by number).
  void share_modes(MPI_Comm comm);

  petsc::OwnedVecScatter to_all_;     // K's layout -> every entry on every rank
  petsc::OwnedVec all_;               // the gathered right side
  std::vector<PetscInt> fluid_row_;   // [k * nf + m]: K's global row of plane k's fluid cell m
  std::vector<PetscInt> plane_of_;    // fluid cell m of a plane: i + nx j
  std::vector<PetscInt> blocked_row_; // K's global rows of blocked cells (identity rows)
  std::vector<double> blocked_diagonal_;
  PetscInt owned_begin_ = 0, owned_end_ = 0;
  // Owned row - owned_begin_ -> (index into owned_planes_) * owned_columns_.size() + index into
  // owned_columns_, or -1 (blocked).
  std::vector<PetscInt> owned_slot_;
  std::vector<PetscInt> owned_planes_, owned_columns_; // the planes k and plane cells m this rank owns
  MPI_Comm comm_ = MPI_COMM_NULL;
  Eigen::MatrixXd modes_; // eigenvectors of T_z (columns)
  Eigen::VectorXd eigenvalues_;
  PetscInt mode_begin_ = 0, mode_end_ = 0;
  std::vector<int> gather_counts_, gather_offsets_; // of coefficients_' entries, by rank
  std::vector<std::unique_ptr<Factor>> factors_;    // of L_xy + lambda_k I for this rank's modes
  mutable Eigen::MatrixXd work_;                    // nz x nf: the right side by plane
  mutable RowMajor coefficients_;                   // nz x nf: by mode, a mode's plane contiguous
  mutable Eigen::MatrixXd owned_values_;            // owned planes x owned columns
  mutable Eigen::VectorXd plane_;                   // one mode's solution
};

} // namespace ibvalve::fluid
