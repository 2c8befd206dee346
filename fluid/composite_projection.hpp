#pragma once
// The composite-grid (Hodge) projection of a normal-velocity field on the composite faces of a hierarchy
// (docs/nested.md). The velocity lives on the faces of CompositeOperators (normal components; the walls
// carry no face, u.n = 0 there), the divergence is D = -V^{-1} G^T W, and the projection is
//     A phi = G^T W u*,   u = u* - G phi,
// so D u = -V^{-1} (G^T W u* - A phi) = 0 to the solver tolerance on every cell of every level, the
// cells beside coarse-fine faces included (Chorin 1968; on composite grids Martin & Colella 2000, here
// with the exact adjoint pair so the projection is an orthogonal projection in the W inner product).
#include <string>

#include "fluid/composite_poisson.hpp"

namespace ibvalve::fluid {

class CompositeProjection {
 public:
  /// `operators` must be built with CompositeBoundary::neumann (closed walls).
  CompositeProjection(const CompositeOperators& operators, const std::string& prefix, double rtol = 1e-12);
  ~CompositeProjection();
  CompositeProjection(const CompositeProjection&) = delete;
  CompositeProjection& operator=(const CompositeProjection&) = delete;

  /// Projects the face vector `u` in place; `phi` (a cell vector) receives the potential. Returns the
  /// solver's iteration count.
  PetscInt project(Vec u, Vec phi) const;

 private:
  const CompositeOperators* operators_;
  CompositePoissonSolver solver_;
};

} // namespace ibvalve::fluid
