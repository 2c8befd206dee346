#include "fe/nodal_system.hpp"

#include <algorithm>
#include <set>

#include "io/petsc_check.hpp"

namespace ibvalve::fe {

NodalSystem::NodalSystem(const Mesh& mesh, int dofs_per_node, MPI_Comm comm)
    : comm_(comm), dofs_(dofs_per_node)
{
  const PetscInt nodes = static_cast<PetscInt>(mesh.num_nodes());
  PetscInt local_nodes = PETSC_DECIDE, total = nodes;
  PETSC_CHECK(PetscSplitOwnership(comm, &local_nodes, &total));
  PetscInt first_node = 0;
  MPI_Scan(&local_nodes, &first_node, 1, MPIU_INT, MPI_SUM, comm);
  first_node -= local_nodes;
  global_ = nodes * dofs_;
  begin_ = first_node * dofs_;
  end_ = (first_node + local_nodes) * dofs_;

  // Node graph of the owned nodes: neighbours through a shared element.
  std::vector<std::set<int>> neighbours(local_nodes);
  for (std::size_t e = 0; e < mesh.num_elements(); ++e) {
    const auto element = mesh.element(e);
    for (int a : element)
      if (a >= first_node && a < first_node + local_nodes)
        for (int b : element) neighbours[a - first_node].insert(b);
  }
  diagonal_nonzeros_.assign(end_ - begin_, 0);
  off_diagonal_nonzeros_.assign(end_ - begin_, 0);
  for (PetscInt n = 0; n < local_nodes; ++n) {
    PetscInt inside = 0;
    for (int b : neighbours[n]) inside += (b >= first_node && b < first_node + local_nodes);
    const PetscInt outside = static_cast<PetscInt>(neighbours[n].size()) - inside;
    for (int d = 0; d < dofs_; ++d) {
      diagonal_nonzeros_[n * dofs_ + d] = inside * dofs_;
      off_diagonal_nonzeros_[n * dofs_ + d] = outside * dofs_;
    }
  }

  const petsc::OwnedVec v = create_vector();
  PETSC_CHECK(VecScatterCreateToAll(v, to_all_.out(), all_.out()));
}

petsc::OwnedMat NodalSystem::create_matrix() const
{
  petsc::OwnedMat matrix;
  PETSC_CHECK(MatCreate(comm_, matrix.out()));
  PETSC_CHECK(MatSetSizes(matrix, end_ - begin_, end_ - begin_, global_, global_));
  PETSC_CHECK(MatSetType(matrix, MATAIJ));
  PETSC_CHECK(MatSetBlockSize(matrix, dofs_));
  PETSC_CHECK(MatSeqAIJSetPreallocation(matrix, 0, diagonal_nonzeros_.data()));
  PETSC_CHECK(
      MatMPIAIJSetPreallocation(matrix, 0, diagonal_nonzeros_.data(), 0, off_diagonal_nonzeros_.data()));
  PETSC_CHECK(MatSetOption(matrix, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  // Dirichlet rows are zeroed and refilled at every Newton step: keep their structure.
  PETSC_CHECK(MatSetOption(matrix, MAT_KEEP_NONZERO_PATTERN, PETSC_TRUE));
  return matrix;
}

petsc::OwnedVec NodalSystem::create_vector() const
{
  petsc::OwnedVec v;
  PETSC_CHECK(VecCreateMPI(comm_, end_ - begin_, global_, v.out()));
  PETSC_CHECK(VecSetBlockSize(v, dofs_));
  return v;
}

void NodalSystem::add_element_matrix(Mat matrix, std::span<const int> nodes,
                                     const Eigen::MatrixXd& element_matrix) const
{
  std::vector<PetscInt> indices;
  indices.reserve(nodes.size() * dofs_);
  for (int n : nodes)
    for (int d = 0; d < dofs_; ++d) indices.push_back(static_cast<PetscInt>(n) * dofs_ + d);
  // PETSc wants row-major values.
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> row_major = element_matrix;
  PETSC_CHECK(MatSetValues(matrix, static_cast<PetscInt>(indices.size()), indices.data(),
                           static_cast<PetscInt>(indices.size()), indices.data(), row_major.data(),
                           ADD_VALUES));
}

std::vector<double> NodalSystem::gather(Vec v) const
{
  PETSC_CHECK(VecScatterBegin(to_all_, v, all_, INSERT_VALUES, SCATTER_FORWARD));
  PETSC_CHECK(VecScatterEnd(to_all_, v, all_, INSERT_VALUES, SCATTER_FORWARD));
  const PetscScalar* values;
  PETSC_CHECK(VecGetArrayRead(all_, &values));
  std::vector<double> result(values, values + global_);
  PETSC_CHECK(VecRestoreArrayRead(all_, &values));
  return result;
}

void NodalSystem::scatter(std::span<const double> replicated, Vec v) const
{
  PetscScalar* values;
  PETSC_CHECK(VecGetArray(v, &values));
  std::copy(replicated.begin() + begin_, replicated.begin() + end_, values);
  PETSC_CHECK(VecRestoreArray(v, &values));
}

namespace {

std::vector<PetscInt> owned_rows(Mat matrix, std::span<const PetscInt> rows)
{
  PetscInt begin = 0, end = 0;
  PETSC_CHECK(MatGetOwnershipRange(matrix, &begin, &end));
  std::vector<PetscInt> owned;
  for (PetscInt r : rows)
    if (r >= begin && r < end) owned.push_back(r);
  return owned;
}

} // namespace

void zero_rows(Mat matrix, std::span<const PetscInt> rows, double diagonal)
{
  const std::vector<PetscInt> owned = owned_rows(matrix, rows);
  PETSC_CHECK(
      MatZeroRows(matrix, static_cast<PetscInt>(owned.size()), owned.data(), diagonal, nullptr, nullptr));
}

void zero_rows_columns(Mat matrix, std::span<const PetscInt> rows, double diagonal, Vec x, Vec b)
{
  // Every rank lists the same (replicated) rows; each passes on the ones it owns.
  const std::vector<PetscInt> owned = owned_rows(matrix, rows);
  PETSC_CHECK(MatZeroRowsColumns(matrix, static_cast<PetscInt>(owned.size()), owned.data(), diagonal, x, b));
}

} // namespace ibvalve::fe
