#include "fluid/composite_poisson.hpp"

#include <cmath>
#include <fmt/format.h>
#include <stdexcept>
#include <string>
#include <utility>

#include "base/errors.hpp"
#include "fluid/boundary.hpp"
#include "io/petsc_check.hpp"

namespace ibvalve::fluid {

namespace {

/// One row of G: columns and coefficients, plus the boundary data part.
struct FaceRow {
  CompositeFace face;
  std::vector<PetscInt> columns;
  std::vector<PetscScalar> values;
  double weight = 0.0;
  double constant = 0.0;
  void add(PetscInt column, double value)
  {
    columns.push_back(column);
    values.push_back(value);
  }
};

/// The row of a coarse-fine face of cell `n` (level l, direction d, side -1 or 1) whose neighbour `next`
/// lies in the coarse cell of level l-1 that holds it: G along +d is side * (U* - u_f) / distance, U*
/// the coarse value, corrected along the face's tangents by the coarse cells beside it with the
/// tangential_linear stencil.
void coarse_fine_row(FaceRow& row, const GridHierarchy& hierarchy, const CompositeCells& cells,
                     CoarseFineStencil stencil, int l, int d, int side, const Index3& next, PetscInt n)
{
  const PetscInt r = hierarchy.ratio(l);
  Index3 coarse;
  for (int e = 0; e < 3; ++e) coarse[e] = next[e] >= 0 ? next[e] / r : -((-next[e] + r - 1) / r);
  const PetscInt c = cells.index(l - 1, coarse);
  if (c < 0) throw std::logic_error("composite grid: a coarse-fine face without an uncovered coarse cell");
  const double h = hierarchy.h(l, d), H = hierarchy.h(l - 1, d);
  const double distance = 0.5 * (h + H);
  row.face.coarse_fine = true;
  row.face.outward = side;
  row.add(n, -side / distance);
  row.add(c, side / distance);
  if (stencil == CoarseFineStencil::tangential_linear) {
    const Real3 X = hierarchy.cell_center(l - 1, coarse);
    for (const int t : {(d + 1) % 3, (d + 2) % 3}) {
      const double delta = row.face.center[t] - X[t];
      const double Ht = hierarchy.h(l - 1, t);
      Index3 up = coarse, down = coarse;
      ++up[t];
      --down[t];
      const PetscInt cu = cells.index(l - 1, up), cd = cells.index(l - 1, down);
      const double s = side / distance * delta;
      if (cu >= 0 && cd >= 0) {
        row.add(cu, s / (2.0 * Ht));
        row.add(cd, -s / (2.0 * Ht));
      } else if (cu >= 0) {
        row.add(cu, s / Ht);
        row.add(c, -s / Ht);
      } else if (cd >= 0) {
        row.add(c, s / Ht);
        row.add(cd, -s / Ht);
      }
    }
  }
  row.weight = hierarchy.h(l, (d + 1) % 3) * hierarchy.h(l, (d + 2) % 3) * distance;
}

/// std::invalid_argument for what the operators cannot do: periodic sides, Dirichlet sides without
/// values, mixed sides without the predicate of their Dirichlet faces.
void check_arguments(const GridHierarchy& hierarchy, CompositeBoundary boundary, bool has_dirichlet_value,
                     bool has_dirichlet_faces)
{
  for (int d = 0; d < 3; ++d)
    if (hierarchy.domain().periodic[d])
      throw std::invalid_argument("composite operators: periodic sides are not supported yet (direction " +
                                  std::string(1, "xyz"[d]) + ")");
  if (boundary == CompositeBoundary::dirichlet && !has_dirichlet_value)
    throw std::invalid_argument("composite operators: Dirichlet sides need boundary values");
  if (boundary == CompositeBoundary::mixed && !has_dirichlet_faces)
    throw std::invalid_argument(
        "composite operators: mixed sides need the predicate of their Dirichlet faces");
}

} // namespace

CompositeOperators::CompositeOperators(MPI_Comm comm, const GridHierarchy& hierarchy,
                                       CoarseFineStencil stencil, CompositeBoundary boundary,
                                       std::function<double(const Real3&)> dirichlet_value,
                                       DirichletFaces dirichlet_faces)
    : comm_(comm), hierarchy_(&hierarchy), cells_(hierarchy), boundary_(boundary),
      dirichlet_faces_(std::move(dirichlet_faces))
{
  check_arguments(hierarchy, boundary, static_cast<bool>(dirichlet_value),
                  static_cast<bool>(dirichlet_faces_));
  const PetscInt total = cells_.size();
  PetscInt owned = PETSC_DECIDE, global = total;
  PETSC_CHECK(PetscSplitOwnership(comm, &owned, &global));
  PetscInt end = 0;
  MPI_Scan(&owned, &end, 1, MPIU_INT, MPI_SUM, comm);
  const PetscInt begin = end - owned;

  std::vector<FaceRow> rows;
  std::vector<double> volumes(owned);
  cells_.for_each(begin, end, [&](PetscInt n, const CompositeCells::Cell& cell) {
    const int l = cell.level;
    volumes[n - begin] = hierarchy.cell_volume(l);
    const Real3 x = hierarchy.cell_center(l, cell.index);
    for (int d = 0; d < 3; ++d) {
      const int t1 = (d + 1) % 3, t2 = (d + 2) % 3;
      const double h = hierarchy.h(l, d), area = hierarchy.h(l, t1) * hierarchy.h(l, t2);
      for (const int side : {-1, 1}) {
        Index3 next = cell.index;
        next[d] += side;
        FaceRow row;
        row.face.normal = d;
        row.face.level = l;
        row.face.area = area;
        row.face.center = x;
        row.face.center[d] += 0.5 * side * h;
        if (!hierarchy.domain_box(l).contains(next)) {
          if (!boundary_face(l, cell.index, side_index(d, side > 0))) continue;
          // (u - g)/(h/2) on the lower side, (g - u)/(h/2) on the upper side.
          row.face.on_boundary = true;
          row.face.side = side_index(d, side > 0);
          row.face.outward = side;
          row.add(n, -side * 2.0 / h);
          row.constant = dirichlet_value ? side * 2.0 / h * dirichlet_value(row.face.center) : 0.0;
          row.weight = area * 0.5 * h;
        } else if (hierarchy.box_containing(l, next) >= 0) {
          if (side > 0 || hierarchy.covered(l, next)) continue; // counted by its upper cell / the finer cells
          row.add(n, 1.0 / h);
          row.add(cells_.index(l, next), -1.0 / h);
          row.weight = area * h;
        } else {
          coarse_fine_row(row, hierarchy, cells_, stencil, l, d, side, next, n);
        }
        rows.push_back(std::move(row));
      }
    }
  });

  const PetscInt local_faces = static_cast<PetscInt>(rows.size());
  PetscInt face_end = 0;
  MPI_Scan(&local_faces, &face_end, 1, MPIU_INT, MPI_SUM, comm);
  const PetscInt face_begin = face_end - local_faces;

  PETSC_CHECK(MatCreateAIJ(comm, local_faces, owned, PETSC_DETERMINE, total, 8, nullptr, 8, nullptr,
                           gradient_.out()));
  PETSC_CHECK(MatSetOption(gradient_, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_FALSE));
  PETSC_CHECK(VecCreateMPI(comm, local_faces, PETSC_DETERMINE, weights_.out()));
  PETSC_CHECK(VecDuplicate(weights_, boundary_part_.out()));
  PETSC_CHECK(VecCreateMPI(comm, owned, total, volumes_.out()));
  for (PetscInt f = 0; f < local_faces; ++f) {
    const FaceRow& row = rows[f];
    const PetscInt global_row = face_begin + f;
    PETSC_CHECK(MatSetValues(gradient_, 1, &global_row, static_cast<PetscInt>(row.columns.size()),
                             row.columns.data(), row.values.data(), ADD_VALUES));
    PETSC_CHECK(VecSetValue(weights_, global_row, row.weight, INSERT_VALUES));
    PETSC_CHECK(VecSetValue(boundary_part_, global_row, row.constant, INSERT_VALUES));
    faces_.push_back(row.face);
  }
  for (PetscInt n = 0; n < owned; ++n)
    PETSC_CHECK(VecSetValue(volumes_, begin + n, volumes[n], INSERT_VALUES));
  PETSC_CHECK(MatAssemblyBegin(gradient_, MAT_FINAL_ASSEMBLY));
  PETSC_CHECK(MatAssemblyEnd(gradient_, MAT_FINAL_ASSEMBLY));
  for (Vec v : {weights_.get(), boundary_part_.get(), volumes_.get()}) {
    PETSC_CHECK(VecAssemblyBegin(v));
    PETSC_CHECK(VecAssemblyEnd(v));
  }

  int local_dirichlet = 0;
  for (const CompositeFace& face : faces_) local_dirichlet = local_dirichlet || face.on_boundary;
  int global_dirichlet = 0;
  MPI_Allreduce(&local_dirichlet, &global_dirichlet, 1, MPI_INT, MPI_MAX, comm);
  any_dirichlet_ = global_dirichlet != 0;

  // A = G^T (W G): symmetric by construction.
  petsc::OwnedMat weighted;
  PETSC_CHECK(MatDuplicate(gradient_, MAT_COPY_VALUES, weighted.out()));
  PETSC_CHECK(MatDiagonalScale(weighted, weights_, nullptr));
  PETSC_CHECK(MatTransposeMatMult(gradient_, weighted, MAT_INITIAL_MATRIX, PETSC_DEFAULT, laplacian_.out()));
}

bool CompositeOperators::boundary_face(int level, const Index3& cell, int side) const
{
  switch (boundary_) {
  case CompositeBoundary::dirichlet:
    return true;
  case CompositeBoundary::neumann:
    return false;
  case CompositeBoundary::mixed:
    break;
  }
  const int d = side / 2;
  Real3 x = hierarchy_->cell_center(level, cell);
  x[d] += (side % 2 == 1 ? 0.5 : -0.5) * hierarchy_->h(level, d);
  return dirichlet_faces_(side, x);
}

petsc::OwnedVec CompositeOperators::create_cell_vector() const
{
  petsc::OwnedVec v;
  PETSC_CHECK(VecDuplicate(volumes_, v.out()));
  PETSC_CHECK(VecSet(v, 0.0));
  return v;
}

petsc::OwnedVec CompositeOperators::create_face_vector() const
{
  petsc::OwnedVec v;
  PETSC_CHECK(VecDuplicate(weights_, v.out()));
  PETSC_CHECK(VecSet(v, 0.0));
  return v;
}

void CompositeOperators::divergence(Vec g, Vec out) const
{
  const petsc::OwnedVec weighted = create_face_vector();
  PETSC_CHECK(VecPointwiseMult(weighted, weights_, g));
  PETSC_CHECK(MatMultTranspose(gradient_, weighted, out));
  PETSC_CHECK(VecPointwiseDivide(out, out, volumes_));
  PETSC_CHECK(VecScale(out, -1.0));
}

void CompositeOperators::sample(const std::function<double(const Real3&)>& u, Vec out) const
{
  PetscInt begin = 0, end = 0;
  PETSC_CHECK(VecGetOwnershipRange(out, &begin, &end));
  PetscScalar* a = nullptr;
  PETSC_CHECK(VecGetArray(out, &a));
  cells_.for_each(begin, end, [&](PetscInt n, const CompositeCells::Cell& cell) {
    a[n - begin] = u(hierarchy_->cell_center(cell.level, cell.index));
  });
  PETSC_CHECK(VecRestoreArray(out, &a));
}

void CompositeOperators::sample_normal(const std::function<Real3(const Real3&)>& v, Vec out) const
{
  PetscScalar* a = nullptr;
  PETSC_CHECK(VecGetArray(out, &a));
  for (std::size_t f = 0; f < faces_.size(); ++f) a[f] = v(faces_[f].center)[faces_[f].normal];
  PETSC_CHECK(VecRestoreArray(out, &a));
}

void CompositeOperators::right_side(const std::function<double(const Real3&)>& f, Vec out) const
{
  sample(f, out);
  PETSC_CHECK(VecPointwiseMult(out, out, volumes_));
  const petsc::OwnedVec wc = create_face_vector(), gtwc = create_cell_vector();
  PETSC_CHECK(VecPointwiseMult(wc, weights_, boundary_part_));
  PETSC_CHECK(MatMultTranspose(gradient_, wc, gtwc));
  PETSC_CHECK(VecAXPY(out, -1.0, gtwc));
}

CompositePoissonSolver::CompositePoissonSolver(const CompositeOperators& operators, bool singular,
                                               const std::string& prefix, double rtol)
{
  PETSC_CHECK(KSPCreate(operators.comm(), ksp_.out()));
  PETSC_CHECK(KSPSetOperators(ksp_, operators.laplacian(), operators.laplacian()));
  PETSC_CHECK(KSPSetType(ksp_, KSPCG));
  PC pc = nullptr;
  PETSC_CHECK(KSPGetPC(ksp_, &pc));
  PETSC_CHECK(PCSetType(pc, PCHYPRE));
  PETSC_CHECK(PCHYPRESetType(pc, "boomeramg"));
  // The true residual is what bounds the divergence left after a projection (D u = -V^{-1} r).
  PETSC_CHECK(KSPSetNormType(ksp_, KSP_NORM_UNPRECONDITIONED));
  PETSC_CHECK(KSPSetTolerances(ksp_, rtol, 1e-50, PETSC_DEFAULT, 1000));
  if (singular) {
    PETSC_CHECK(MatNullSpaceCreate(operators.comm(), PETSC_TRUE, 0, nullptr, null_space_.out()));
    PETSC_CHECK(MatSetNullSpace(operators.laplacian(), null_space_));
  }
  PETSC_CHECK(KSPSetOptionsPrefix(ksp_, prefix.c_str()));
  PETSC_CHECK(KSPSetFromOptions(ksp_));
}

PetscInt CompositePoissonSolver::solve(Vec b, Vec x) const
{
  if (null_space_) PETSC_CHECK(MatNullSpaceRemove(null_space_, b));
  PETSC_CHECK(KSPSolve(ksp_, b, x));
  KSPConvergedReason reason;
  PETSC_CHECK(KSPGetConvergedReason(ksp_, &reason));
  PetscInt iterations = 0;
  PETSC_CHECK(KSPGetIterationNumber(ksp_, &iterations));
  if (reason < 0)
    throw RunError(fmt::format("composite Poisson solver diverged ({}) after {} iterations",
                               KSPConvergedReasons[reason], iterations));
  return iterations;
}

} // namespace ibvalve::fluid
