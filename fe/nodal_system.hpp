#pragma once
// PETSc matrices and vectors over the nodes of a replicated mesh: nodes are owned in contiguous
// blocks by the ranks (dofs_per_node unknowns each, interlaced), the matrix is preallocated from the
// mesh's node graph, and each rank adds the element matrices of its own element range (PETSc sends
// entries of rows it does not own to their owner at assembly).
#include <span>
#include <vector>

#include <Eigen/Core>
#include <petscmat.h>

#include "fe/mesh.hpp"
#include "io/petsc_handle.hpp"

namespace ibvalve::fe {

class NodalSystem {
 public:
  NodalSystem(const Mesh& mesh, int dofs_per_node, MPI_Comm comm);
  NodalSystem(const NodalSystem&) = delete;
  NodalSystem& operator=(const NodalSystem&) = delete;

  MPI_Comm comm() const { return comm_; }
  int dofs_per_node() const { return dofs_; }
  PetscInt global_size() const { return global_; }
  /// This rank's rows [begin, end).
  PetscInt owned_begin() const { return begin_; }
  PetscInt owned_end() const { return end_; }

  /// A new matrix with the right layout and preallocation (zero).
  petsc::OwnedMat create_matrix() const;
  /// A new vector with the layout of the unknowns.
  petsc::OwnedVec create_vector() const;

  /// Adds an element matrix: rows and columns are the unknowns of `nodes` (node-major, dof-minor).
  void add_element_matrix(Mat matrix, std::span<const int> nodes,
                          const Eigen::MatrixXd& element_matrix) const;

  /// The whole vector on every rank.
  std::vector<double> gather(Vec v) const;
  /// Sets this rank's entries of `v` from a replicated array.
  void scatter(std::span<const double> replicated, Vec v) const;

 private:
  MPI_Comm comm_;
  int dofs_ = 1;
  PetscInt global_ = 0, begin_ = 0, end_ = 0;
  std::vector<PetscInt> diagonal_nonzeros_, off_diagonal_nonzeros_;
  petsc::OwnedVecScatter to_all_;
  petsc::OwnedVec all_;
};

/// Zeroes rows and columns `rows` (global indices, the same list on every rank) of an assembled matrix,
/// puts `diagonal` on their diagonal and, when x and b are given, moves the known values x into b
/// (PETSc MatZeroRowsColumns). Keeps a symmetric matrix symmetric.
void zero_rows_columns(Mat matrix, std::span<const PetscInt> rows, double diagonal, Vec x = nullptr,
                       Vec b = nullptr);

/// Zeroes rows `rows` (the same list on every rank) of an assembled matrix and puts `diagonal` on
/// their diagonal (PETSc MatZeroRows); the columns are kept.
void zero_rows(Mat matrix, std::span<const PetscInt> rows, double diagonal);

} // namespace ibvalve::fe
