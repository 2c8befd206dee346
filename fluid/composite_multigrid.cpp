#include "fluid/composite_multigrid.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>

#include "io/petsc_check.hpp"

namespace ibvalve::fluid {

namespace {

// A cell of some space: its spacing as a power of two of the finest spacing, then its index at that
// spacing (z, y, x: sorted keys number a space z-major).
using SpaceKey = std::array<PetscInt, 4>;

int exact_log2(PetscInt ratio)
{
  int e = 0;
  while ((PetscInt{1} << e) < ratio) ++e;
  if ((PetscInt{1} << e) != ratio)
    throw std::invalid_argument("composite multigrid: every refinement ratio must be a power of two");
  return e;
}

/// The first global row of this rank when `local` rows are split in rank order.
PetscInt first_row(MPI_Comm comm, PetscInt local)
{
  PetscInt end = 0;
  MPI_Scan(&local, &end, 1, MPIU_INT, MPI_SUM, comm);
  return end - local;
}

petsc::OwnedMat assembled(MPI_Comm comm, PetscInt rows, PetscInt columns, PetscInt global_columns,
                          PetscInt nonzeros)
{
  petsc::OwnedMat m;
  PETSC_CHECK(MatCreateAIJ(comm, rows, columns, PETSC_DETERMINE, global_columns, nonzeros, nullptr, nonzeros,
                           nullptr, m.out()));
  return m;
}

} // namespace

CompositeCoarsening composite_coarsening(MPI_Comm comm, const CompositeCells& cells, PetscInt local_cells,
                                         PetscInt coarsest)
{
  const GridHierarchy& h = cells.hierarchy();
  std::vector<PetscInt> exponent(static_cast<std::size_t>(h.levels()), 0);
  for (int l = h.finest() - 1; l >= 0; --l)
    exponent[static_cast<std::size_t>(l)] =
        exponent[static_cast<std::size_t>(l + 1)] + exact_log2(h.ratio(l + 1));
  // The current space's cells in its global order, on every rank (as the composite numbering is).
  std::vector<SpaceKey> keys(static_cast<std::size_t>(cells.size()));
  cells.for_each(0, cells.size(), [&](PetscInt n, const CompositeCells::Cell& c) {
    keys[static_cast<std::size_t>(n)] = {exponent[static_cast<std::size_t>(c.level)], c.index[2], c.index[1],
                                         c.index[0]};
  });
  PetscInt local = local_cells;
  CompositeCoarsening out;
  for (PetscInt m = 1; static_cast<PetscInt>(keys.size()) > coarsest; ++m) {
    // The cells of spacing m - 1 (the finest present) merge two by two along every direction.
    std::vector<SpaceKey> parent(keys.size());
    for (std::size_t n = 0; n < keys.size(); ++n)
      parent[n] = keys[n][0] < m ? SpaceKey{m, keys[n][1] >> 1, keys[n][2] >> 1, keys[n][3] >> 1} : keys[n];
    std::vector<SpaceKey> coarse = parent;
    std::sort(coarse.begin(), coarse.end());
    coarse.erase(std::unique(coarse.begin(), coarse.end()), coarse.end());
    if (coarse.size() == keys.size()) break;
    const auto find = [&](const SpaceKey& k) -> PetscInt {
      const auto it = std::lower_bound(coarse.begin(), coarse.end(), k);
      return it != coarse.end() && *it == k ? static_cast<PetscInt>(it - coarse.begin()) : -1;
    };
    PetscInt size = static_cast<PetscInt>(coarse.size()), coarse_local = PETSC_DECIDE;
    PETSC_CHECK(PetscSplitOwnership(comm, &coarse_local, &size));
    petsc::OwnedMat aggregation = assembled(comm, local, coarse_local, size, 1);
    petsc::OwnedMat interpolation = assembled(comm, local, coarse_local, size, 8);
    const PetscInt begin = first_row(comm, local);
    for (PetscInt n = begin; n < begin + local; ++n) {
      const SpaceKey& fine = keys[static_cast<std::size_t>(n)];
      const SpaceKey& p = parent[static_cast<std::size_t>(n)];
      const PetscInt own = find(p);
      PETSC_CHECK(MatSetValue(aggregation, n, own, 1.0, INSERT_VALUES));
      std::array<PetscInt, 8> columns{own};
      std::array<PetscScalar, 8> weights{1.0};
      PetscInt count = 1;
      if (fine[0] < m) {
        // Trilinear: per direction 3/4 of the parent and 1/4 of its neighbour on the fine cell's side.
        bool all = true;
        for (int c = 0; c < 8 && all; ++c) {
          SpaceKey k = p;
          double w = 1.0;
          for (std::size_t d = 1; d <= 3; ++d) {
            const bool across = ((c >> (d - 1)) & 1) != 0;
            if (across) k[d] += (fine[d] & 1) != 0 ? 1 : -1;
            w *= across ? 0.25 : 0.75;
          }
          columns[static_cast<std::size_t>(c)] = find(k);
          weights[static_cast<std::size_t>(c)] = w;
          all = columns[static_cast<std::size_t>(c)] >= 0;
        }
        if (all) {
          count = 8;
        } else { // the first of the eight was the parent itself, at 27/64
          columns[0] = own;
          weights[0] = 1.0;
        }
      }
      PETSC_CHECK(MatSetValues(interpolation, 1, &n, count, columns.data(), weights.data(), INSERT_VALUES));
    }
    for (Mat a : {aggregation.get(), interpolation.get()}) {
      PETSC_CHECK(MatAssemblyBegin(a, MAT_FINAL_ASSEMBLY));
      PETSC_CHECK(MatAssemblyEnd(a, MAT_FINAL_ASSEMBLY));
    }
    out.aggregations.push_back(std::move(aggregation));
    out.interpolations.push_back(std::move(interpolation));
    keys = std::move(coarse);
    local = coarse_local;
  }
  return out;
}

void set_composite_multigrid(PC pc, Mat coarsening, const CompositeCells& cells, PetscInt coarsest)
{
  MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(pc));
  PetscInt local = 0;
  PETSC_CHECK(MatGetLocalSize(coarsening, &local, nullptr));
  const CompositeCoarsening spaces = composite_coarsening(comm, cells, local, coarsest);
  const auto levels = static_cast<PetscInt>(spaces.interpolations.size()) + 1;
  PETSC_CHECK(PCSetType(pc, PCMG));
  PETSC_CHECK(PCMGSetLevels(pc, levels, nullptr));
  PETSC_CHECK(PCMGSetGalerkin(pc, PC_MG_GALERKIN_NONE));
  Mat finer = coarsening;
  petsc::OwnedMat previous; // the operator of the space above, while the next is made from it
  for (std::size_t m = 0; m < spaces.interpolations.size(); ++m) {
    // PCMG numbers its levels from the coarsest (0); space m is level levels - 1 - m. The PC and the
    // level solvers take references: the matrices may go when this function ends.
    const PetscInt level = levels - 1 - static_cast<PetscInt>(m);
    PETSC_CHECK(PCMGSetInterpolation(pc, level, spaces.interpolations[m]));
    PETSC_CHECK(PCMGSetRestriction(pc, level, spaces.aggregations[m]));
    petsc::OwnedMat coarse;
    PETSC_CHECK(MatPtAP(finer, spaces.aggregations[m], MAT_INITIAL_MATRIX, 2.0, coarse.out()));
    PETSC_CHECK(MatScale(coarse, 0.5));
    KSP smoother = nullptr;
    PETSC_CHECK(PCMGGetSmoother(pc, level - 1, &smoother));
    PETSC_CHECK(KSPSetOperators(smoother, coarse, coarse));
    previous = std::move(coarse);
    finer = previous;
  }
  // One SOR sweep (PETSc's local symmetric Gauss-Seidel) a level each way, in a W-cycle, unless the
  // options database says otherwise (-<prefix>mg_levels_..., -<prefix>pc_mg_cycle_type): with V-cycles
  // the coarse correction is the weak part (17 GMRES iterations on the study's valve grid against 12).
  PETSC_CHECK(PCMGSetCycleType(pc, PC_MG_CYCLE_W));
  for (PetscInt level = 1; level < levels; ++level) {
    KSP smoother = nullptr;
    PETSC_CHECK(PCMGGetSmoother(pc, level, &smoother));
    PETSC_CHECK(KSPSetType(smoother, KSPRICHARDSON));
    PETSC_CHECK(KSPSetTolerances(smoother, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT, 1));
    PC sweep = nullptr;
    PETSC_CHECK(KSPGetPC(smoother, &sweep));
    PETSC_CHECK(PCSetType(sweep, PCSOR));
  }
}

} // namespace ibvalve::fluid
