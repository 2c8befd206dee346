#pragma once
// A geometric multigrid for the composite pressure operators of nested levels (docs/nested.md, "The
// projection's multigrid"), selected by the option -<prefix>pressure_composite_multigrid.
//
// Coarse spaces: each coarser space merges the cells of the finest spacing present two by two along every
// direction, so the finest level coarsens until it reaches the spacing of the level below and joins that
// level's uncovered cells, and so on, until the whole grid is one uniform grid, which then coarsens on.
// A cell is named by its spacing (a power of two of the finest) and its index at that spacing, so the
// spaces need no geometry beyond the composite numbering. Transfers are those of cell-centred multigrid
// (Wesseling 1992, An Introduction to Multigrid Methods, ch. 5; Khalil & Wesseling 1992, J. Comput. Phys.
// 98:1): restriction by the sum over the merged cells (the transpose of piecewise-constant aggregation),
// interpolation trilinear in the cell centres (3/4 of the parent and 1/4 of its neighbour on the cell's
// side, per direction) where all eight coarse cells exist, piecewise constant elsewhere. The coarse
// operators are half the aggregation's Galerkin products: in the integrated operator G^T W G a face
// weighs its area over the centres' distance, so a coarse face of the product gathers four fine faces of
// h^2/h, 4h in all, where the coarse face rediscretized weighs H^2/H = 2h; the halved product is the
// operator rediscretized on the coarse cells (exactly so away from interfaces and sides).
#include <vector>

#include <petscksp.h>

#include "fluid/composite_cells.hpp"
#include "io/petsc_handle.hpp"

namespace ibvalve::fluid {

/// The transfers between the composite cells (space 0, rows split as the composite cell vectors, this
/// rank's `local_cells` of them) and successively coarser spaces, until a space has at most `coarsest`
/// cells or stops shrinking. Entry m maps space m + 1 to space m. Every refinement ratio must be a power
/// of two. Collective on `comm`.
struct CompositeCoarsening {
  std::vector<petsc::OwnedMat> interpolations; // trilinear where possible
  std::vector<petsc::OwnedMat> aggregations;   // piecewise constant; restriction by the transpose
};
CompositeCoarsening composite_coarsening(MPI_Comm comm, const CompositeCells& cells, PetscInt local_cells,
                                         PetscInt coarsest);

/// Makes `pc` a PCMG on the spaces of composite_coarsening, one SOR sweep a level each way and W-cycles
/// (the options database may choose others). The composite cells (space 0) are smoothed with the PC's
/// own preconditioning matrix; the coarser spaces' operators are the halved aggregation products
/// described above, starting from `coarsening`, a composite cell matrix: the PC's matrix itself, or a
/// sparser operator of the same problem (the two-point Laplacian for the consistent projection, whose
/// Galerkin products would be denser and no better). Collective.
void set_composite_multigrid(PC pc, Mat coarsening, const CompositeCells& cells, PetscInt coarsest = 500);

} // namespace ibvalve::fluid
