#pragma once
// Discrete norms on the composite grid of nested levels, as the nested fluid tests measure their errors:
// the max norm, and the L2 norm weighted by each face's dual volume W (face vectors) or each cell's volume
// (cell vectors), divided by the total weight so that it compares with the continuous norm over the box.
#include <cmath>

#include "fluid/composite_poisson.hpp"
#include "io/petsc_check.hpp"

namespace ibvalve::fluid::testing {

struct CompositeNorms {
  double max = 0.0;
  double l2 = 0.0;
};

/// sqrt(sum_i w_i e_i^2 / sum_i w_i) and max |e_i| of e with the weights w (collective).
inline CompositeNorms weighted_norms(Vec e, Vec w)
{
  CompositeNorms n;
  PETSC_CHECK(VecNorm(e, NORM_INFINITY, &n.max));
  petsc::OwnedVec squared;
  PETSC_CHECK(VecDuplicate(e, squared.out()));
  PETSC_CHECK(VecPointwiseMult(squared, e, e));
  double weighted = 0.0, total = 0.0;
  PETSC_CHECK(VecDot(squared, w, &weighted));
  PETSC_CHECK(VecSum(w, &total));
  n.l2 = std::sqrt(weighted / total);
  return n;
}

/// Norms of a face vector (normal velocities), weighted by the faces' dual volumes.
inline CompositeNorms face_norms(const CompositeOperators& ops, Vec e)
{
  return weighted_norms(e, ops.weights());
}

/// Norms of a cell vector (pressures), weighted by the cells' volumes.
inline CompositeNorms cell_norms(const CompositeOperators& ops, Vec e)
{
  return weighted_norms(e, ops.volumes());
}

/// Norms of u - exact on the faces, the exact normal velocity sampled at each face centre.
template <class Velocity>
CompositeNorms face_error(const CompositeOperators& ops, const Velocity& exact, Vec u)
{
  const petsc::OwnedVec e = ops.create_face_vector();
  ops.sample_normal(exact, e);
  PETSC_CHECK(VecAXPY(e, -1.0, u));
  return face_norms(ops, e);
}

} // namespace ibvalve::fluid::testing
