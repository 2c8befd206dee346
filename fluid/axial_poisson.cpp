#include "fluid/axial_poisson.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include <Eigen/Eigenvalues>

#include "io/petsc_check.hpp"

namespace ibvalve::fluid {

namespace {

/// Each pressure unknown's cell as i + nx (j + ny k), gathered onto every rank in K's numbering.
std::vector<PetscInt> cells_of_rows(const StaggeredGrid& grid, IS is_p, Vec layout, VecScatter to_all,
                                    Vec all)
{
  petsc::OwnedVec local = grid.create_local(), whole = grid.create_global();
  const PetscInt nx = grid.cells(0), ny = grid.cells(1);
  {
    StagArray a(grid, local);
    for (PetscInt k = grid.begin(2); k < grid.begin(2) + grid.count(2); ++k)
      for (PetscInt j = grid.begin(1); j < grid.begin(1) + grid.count(1); ++j)
        for (PetscInt i = grid.begin(0); i < grid.begin(0) + grid.count(0); ++i)
          a(i, j, k, grid.pressure_slot()) = static_cast<double>(i + nx * (j + ny * k));
  }
  PETSC_CHECK(DMLocalToGlobal(grid.dm(), local, INSERT_VALUES, whole));
  petsc::OwnedVec codes;
  PETSC_CHECK(VecDuplicate(layout, codes.out()));
  PETSC_CHECK(VecISCopy(whole, is_p, SCATTER_REVERSE, codes));
  PETSC_CHECK(VecScatterBegin(to_all, codes, all, INSERT_VALUES, SCATTER_FORWARD));
  PETSC_CHECK(VecScatterEnd(to_all, codes, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscInt n = 0;
  PETSC_CHECK(VecGetSize(all, &n));
  std::vector<PetscInt> cell(static_cast<std::size_t>(n));
  const PetscScalar* c = nullptr;
  PETSC_CHECK(VecGetArrayRead(all, &c));
  for (PetscInt r = 0; r < n; ++r)
    cell[static_cast<std::size_t>(r)] = static_cast<PetscInt>(std::llround(c[r]));
  PETSC_CHECK(VecRestoreArrayRead(all, &c));
  return cell;
}

bool close(double a, double b, double scale)
{
  return std::abs(a - b) <= 1e-10 * scale;
}

/// A row of K: its diagonal and its couplings by neighbour cell.
struct Row {
  double diagonal = 0.0;
  std::map<PetscInt, double> off;
};

/// K's rows by cell (i + nx (j + ny k)) from the sequential copy `whole`; `scale` its largest entry.
std::vector<Row> rows_by_cell(Mat whole, const std::vector<PetscInt>& cell, double& scale)
{
  std::vector<Row> row(cell.size());
  scale = 0.0;
  for (PetscInt r = 0; r < static_cast<PetscInt>(cell.size()); ++r) {
    PetscInt n = 0;
    const PetscInt* columns = nullptr;
    const PetscScalar* values = nullptr;
    PETSC_CHECK(MatGetRow(whole, r, &n, &columns, &values));
    Row& here = row[static_cast<std::size_t>(cell[static_cast<std::size_t>(r)])];
    for (PetscInt e = 0; e < n; ++e) {
      scale = std::max(scale, std::abs(values[e]));
      if (columns[e] == r)
        here.diagonal += values[e];
      else if (values[e] != 0.0)
        here.off[cell[static_cast<std::size_t>(columns[e])]] += values[e];
    }
    PETSC_CHECK(MatRestoreRow(whole, r, &n, &columns, &values));
  }
  return row;
}

/// K split as I_xy (x) T_z + L_xy (x) I_z on the fluid cells of a plane (those with a coupling in plane
/// 0), read off the rows; `separable` tells whether every row agrees with the split.
struct Split {
  std::vector<PetscInt> plane_of;       // fluid cell m -> i + nx j
  std::vector<PetscInt> index_in_plane; // i + nx j -> m, or -1 (blocked)
  Eigen::MatrixXd tz;
  std::vector<double> lxy_diagonal;
  std::vector<Eigen::Triplet<double>> lxy; // L_xy's entries, its diagonal included
  bool separable = false;
};

/// Whether the fluid row of cell c in plane k agrees with the split, and L_xy's entries from plane 0.
bool row_agrees(const std::vector<Row>& row, Split& s, PetscInt plane, PetscInt k, PetscInt c, double scale)
{
  const Row& r = row[static_cast<std::size_t>(c + plane * k)];
  const PetscInt m = s.index_in_plane[static_cast<std::size_t>(c)];
  if (m < 0) return r.off.empty();
  bool agrees = close(r.diagonal, s.lxy_diagonal[static_cast<std::size_t>(m)] + s.tz(k, k), scale);
  PetscInt z_neighbours = 0;
  std::size_t in_plane = 0;
  const auto& first = row[static_cast<std::size_t>(c)].off;
  for (const auto& [nb, v] : r.off) {
    const PetscInt nb_plane = nb / plane, nb_cell = nb % plane;
    if (nb_plane != k) {
      agrees = agrees && nb_cell == c && close(v, s.tz(k, nb_plane), scale);
      ++z_neighbours;
      continue;
    }
    const PetscInt n = s.index_in_plane[static_cast<std::size_t>(nb_cell)];
    const auto it = first.find(nb_cell);
    agrees = agrees && n >= 0 && it != first.end() && close(v, it->second, scale);
    if (k == 0 && n >= 0) s.lxy.emplace_back(m, n, v);
    ++in_plane;
  }
  for (PetscInt kk = 0; kk < s.tz.rows(); ++kk)
    if (kk != k && s.tz(k, kk) != 0.0) --z_neighbours;
  // As many in-plane neighbours as in plane 0 (whose entries those of plane k matched).
  std::size_t first_in_plane = 0;
  for (const auto& nb : first)
    if (nb.first / plane == 0) ++first_in_plane;
  return agrees && z_neighbours == 0 && in_plane == first_in_plane;
}

Split split(const std::vector<Row>& row, PetscInt plane, PetscInt nz, double scale)
{
  Split s;
  s.index_in_plane.assign(static_cast<std::size_t>(plane), -1);
  for (PetscInt c = 0; c < plane; ++c)
    if (!row[static_cast<std::size_t>(c)].off.empty()) {
      s.index_in_plane[static_cast<std::size_t>(c)] = static_cast<PetscInt>(s.plane_of.size());
      s.plane_of.push_back(c);
    }
  const auto nf = static_cast<PetscInt>(s.plane_of.size());
  if (nf == 0) return s;
  // T_z from the first fluid column; L_xy's diagonal from a middle plane, where a column's z part is
  // minus the sum of its z neighbours.
  const PetscInt c0 = s.plane_of[0], km = nz / 2;
  s.tz = Eigen::MatrixXd::Zero(nz, nz);
  for (PetscInt k = 0; k < nz; ++k)
    for (const auto& [nb, v] : row[static_cast<std::size_t>(c0 + plane * k)].off)
      if (nb % plane == c0) s.tz(k, nb / plane) = v;
  s.lxy_diagonal.resize(static_cast<std::size_t>(nf));
  for (PetscInt m = 0; m < nf; ++m) {
    const Row& r = row[static_cast<std::size_t>(s.plane_of[static_cast<std::size_t>(m)] + plane * km)];
    double z_sum = 0.0;
    for (const auto& [nb, v] : r.off)
      if (nb / plane != km) z_sum -= v;
    s.lxy_diagonal[static_cast<std::size_t>(m)] = r.diagonal - z_sum;
  }
  for (PetscInt k = 0; k < nz; ++k)
    s.tz(k, k) = row[static_cast<std::size_t>(c0 + plane * k)].diagonal - s.lxy_diagonal[0];
  s.separable = s.tz.isApprox(s.tz.transpose(), 1e-12);
  for (PetscInt k = 0; k < nz && s.separable; ++k)
    for (PetscInt c = 0; c < plane && s.separable; ++c) s.separable = row_agrees(row, s, plane, k, c, scale);
  for (PetscInt m = 0; m < nf; ++m) s.lxy.emplace_back(m, m, s.lxy_diagonal[static_cast<std::size_t>(m)]);
  return s;
}

} // namespace

std::unique_ptr<AxialPoisson> AxialPoisson::make(const StaggeredGrid& grid, Mat K, IS is_p)
{
  const PetscInt plane = grid.cells(0) * grid.cells(1), nz = grid.cells(2);
  if (grid.periodic(2)) return nullptr;
  // One gather onto every rank serves the cells' labels here and each solve's right side.
  petsc::OwnedVec layout, all;
  petsc::OwnedVecScatter to_all;
  PETSC_CHECK(MatCreateVecs(K, layout.out(), nullptr));
  PETSC_CHECK(VecScatterCreateToAll(layout, to_all.out(), all.out()));
  const std::vector<PetscInt> cell = cells_of_rows(grid, is_p, layout, to_all, all);
  // The whole of K on every rank (one sequential copy each): every rank decides alike.
  int size = 1;
  MPI_Comm_size(grid.comm(), &size);
  petsc::OwnedMat whole;
  PETSC_CHECK(MatCreateRedundantMatrix(K, size, MPI_COMM_NULL, MAT_INITIAL_MATRIX, whole.out()));
  double scale = 0.0;
  const std::vector<Row> row = rows_by_cell(whole, cell, scale);
  Split s = split(row, plane, nz, scale);
  if (!s.separable) return nullptr;

  std::unique_ptr<AxialPoisson> solver(new AxialPoisson());
  // T_z = Q diag(lambda) Q^T; a factor of L_xy + lambda_k I for each of this rank's modes.
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(s.tz);
  solver->modes_ = eigen.eigenvectors();
  solver->eigenvalues_ = eigen.eigenvalues();
  // A zero mode along z (no open end) leaves L_xy, closed by walls, singular: multigrid keeps it.
  if (solver->eigenvalues_.minCoeff() <= 1e-10 * scale) return nullptr;
  solver->plane_of_ = std::move(s.plane_of);
  const auto nf = static_cast<PetscInt>(solver->plane_of_.size());
  solver->share_modes(grid.comm());
  Eigen::SparseMatrix<double> l(nf, nf), identity(nf, nf);
  l.setFromTriplets(s.lxy.begin(), s.lxy.end());
  identity.setIdentity();
  int failed = 0;
  for (PetscInt k = solver->mode_begin_; k < solver->mode_end_ && !failed; ++k) {
    auto factor = std::make_unique<Factor>();
    factor->compute(l + solver->eigenvalues_(k) * identity);
    failed = factor->info() != Eigen::Success;
    solver->factors_.push_back(std::move(factor));
  }
  // Every rank decides alike: a factor that fails on one rank fails the choice on all.
  MPI_Allreduce(MPI_IN_PLACE, &failed, 1, MPI_INT, MPI_MAX, grid.comm());
  if (failed) return nullptr;
  std::vector<PetscInt> row_of(cell.size());
  for (std::size_t r = 0; r < cell.size(); ++r)
    row_of[static_cast<std::size_t>(cell[r])] = static_cast<PetscInt>(r);
  std::vector<double> diagonal(cell.size());
  for (std::size_t r = 0; r < cell.size(); ++r) diagonal[r] = row[static_cast<std::size_t>(cell[r])].diagonal;
  solver->place_rows(K, row_of, diagonal);
  solver->to_all_ = std::move(to_all);
  solver->all_ = std::move(all);
  return solver;
}

void AxialPoisson::share_modes(MPI_Comm comm)
{
  comm_ = comm;
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const auto nz = static_cast<PetscInt>(eigenvalues_.size()), nf = static_cast<PetscInt>(plane_of_.size());
  const auto first = [&](int p) { return nz * p / size; };
  mode_begin_ = first(rank);
  mode_end_ = first(rank + 1);
  gather_counts_.resize(static_cast<std::size_t>(size));
  gather_offsets_.resize(static_cast<std::size_t>(size));
  for (int p = 0; p < size; ++p) {
    gather_offsets_[static_cast<std::size_t>(p)] = static_cast<int>(first(p) * nf);
    gather_counts_[static_cast<std::size_t>(p)] = static_cast<int>((first(p + 1) - first(p)) * nf);
  }
}

void AxialPoisson::place_rows(Mat K, const std::vector<PetscInt>& row_of, const std::vector<double>& diagonal)
{
  const auto nz = static_cast<PetscInt>(eigenvalues_.size()), nf = static_cast<PetscInt>(plane_of_.size());
  const PetscInt plane = static_cast<PetscInt>(row_of.size()) / nz;
  fluid_row_.resize(static_cast<std::size_t>(nz * nf));
  for (PetscInt k = 0; k < nz; ++k)
    for (PetscInt m = 0; m < nf; ++m)
      fluid_row_[static_cast<std::size_t>(k * nf + m)] =
          row_of[static_cast<std::size_t>(plane_of_[static_cast<std::size_t>(m)] + plane * k)];
  PETSC_CHECK(MatGetOwnershipRange(K, &owned_begin_, &owned_end_));
  // The planes and plane cells this rank owns: the back transform computes their product only.
  std::vector<PetscInt> slot_of(static_cast<std::size_t>(owned_end_ - owned_begin_), -1);
  std::vector<char> plane_owned(static_cast<std::size_t>(nz), 0),
      column_owned(static_cast<std::size_t>(nf), 0);
  for (PetscInt slot = 0; slot < nz * nf; ++slot) {
    const PetscInt r = fluid_row_[static_cast<std::size_t>(slot)];
    if (r < owned_begin_ || r >= owned_end_) continue;
    slot_of[static_cast<std::size_t>(r - owned_begin_)] = slot;
    plane_owned[static_cast<std::size_t>(slot / nf)] = column_owned[static_cast<std::size_t>(slot % nf)] = 1;
  }
  // The owned ones listed in order into `list`; returned: each one's place in it, or -1.
  auto number_owned = [](const std::vector<char>& owned, std::vector<PetscInt>& list) {
    std::vector<PetscInt> index(owned.size(), -1);
    for (std::size_t i = 0; i < owned.size(); ++i)
      if (owned[i]) {
        index[i] = static_cast<PetscInt>(list.size());
        list.push_back(static_cast<PetscInt>(i));
      }
    return index;
  };
  const std::vector<PetscInt> plane_index = number_owned(plane_owned, owned_planes_),
                              column_index = number_owned(column_owned, owned_columns_);
  const auto columns = static_cast<PetscInt>(owned_columns_.size());
  owned_slot_.assign(slot_of.size(), -1);
  for (PetscInt r = owned_begin_; r < owned_end_; ++r) {
    const PetscInt slot = slot_of[static_cast<std::size_t>(r - owned_begin_)];
    if (slot >= 0) {
      owned_slot_[static_cast<std::size_t>(r - owned_begin_)] =
          plane_index[static_cast<std::size_t>(slot / nf)] * columns +
          column_index[static_cast<std::size_t>(slot % nf)];
    } else {
      blocked_row_.push_back(r);
      blocked_diagonal_.push_back(diagonal[static_cast<std::size_t>(r)]);
    }
  }
  work_.resize(nz, nf);
  coefficients_.resize(nz, nf);
  owned_values_.resize(static_cast<Eigen::Index>(owned_planes_.size()), columns);
  plane_.resize(nf);
}

void AxialPoisson::solve(Vec r, Vec phi) const
{
  PETSC_CHECK(VecScatterBegin(to_all_, r, all_, INSERT_VALUES, SCATTER_FORWARD));
  PETSC_CHECK(VecScatterEnd(to_all_, r, all_, INSERT_VALUES, SCATTER_FORWARD));
  const auto nz = static_cast<PetscInt>(eigenvalues_.size()), nf = static_cast<PetscInt>(plane_of_.size());
  {
    const PetscScalar* b = nullptr;
    PETSC_CHECK(VecGetArrayRead(all_, &b));
    for (PetscInt k = 0; k < nz; ++k)
      for (PetscInt m = 0; m < nf; ++m) work_(k, m) = b[fluid_row_[static_cast<std::size_t>(k * nf + m)]];
    PETSC_CHECK(VecRestoreArrayRead(all_, &b));
  }
  // Along z into this rank's modes, each mode's plane solved, then every rank's modes to every rank.
  const PetscInt mine = mode_end_ - mode_begin_;
  coefficients_.middleRows(mode_begin_, mine).noalias() =
      modes_.middleCols(mode_begin_, mine).transpose() * work_;
  for (PetscInt k = mode_begin_; k < mode_end_; ++k) {
    plane_ = factors_[static_cast<std::size_t>(k - mode_begin_)]->solve(coefficients_.row(k).transpose());
    coefficients_.row(k) = plane_.transpose();
  }
  MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, coefficients_.data(), gather_counts_.data(),
                 gather_offsets_.data(), MPI_DOUBLE, comm_);
  // Back along z, on the planes and plane cells this rank owns.
  owned_values_.noalias() = modes_(owned_planes_, Eigen::all) * coefficients_(Eigen::all, owned_columns_);
  PetscScalar* x = nullptr;
  const PetscScalar* b = nullptr;
  PETSC_CHECK(VecGetArray(phi, &x));
  PETSC_CHECK(VecGetArrayRead(r, &b));
  const auto columns = static_cast<PetscInt>(owned_columns_.size());
  for (PetscInt o = 0; o < owned_end_ - owned_begin_; ++o) {
    const PetscInt slot = owned_slot_[static_cast<std::size_t>(o)];
    if (slot >= 0) x[o] = owned_values_(slot / columns, slot % columns);
  }
  for (std::size_t n = 0; n < blocked_row_.size(); ++n) {
    const PetscInt o = blocked_row_[n] - owned_begin_;
    x[o] = b[o] / blocked_diagonal_[n];
  }
  PETSC_CHECK(VecRestoreArrayRead(r, &b));
  PETSC_CHECK(VecRestoreArray(phi, &x));
}

} // namespace ibvalve::fluid
