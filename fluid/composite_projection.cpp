#include "fluid/composite_projection.hpp"

#include "io/petsc_check.hpp"

namespace ibvalve::fluid {

CompositeProjection::CompositeProjection(const CompositeOperators& operators, const std::string& prefix,
                                         double rtol)
    : operators_(&operators), solver_(operators, true, prefix, rtol)
{
}

CompositeProjection::~CompositeProjection() = default;

PetscInt CompositeProjection::project(Vec u, Vec phi) const
{
  const petsc::OwnedVec weighted = operators_->create_face_vector(), rhs = operators_->create_cell_vector(),
                        correction = operators_->create_face_vector();
  PETSC_CHECK(VecPointwiseMult(weighted, operators_->weights(), u));
  PETSC_CHECK(MatMultTranspose(operators_->gradient(), weighted, rhs));
  PETSC_CHECK(VecSet(phi, 0.0));
  const PetscInt iterations = solver_.solve(rhs, phi);
  PETSC_CHECK(MatMult(operators_->gradient(), phi, correction));
  PETSC_CHECK(VecAXPY(u, -1.0, correction));
  return iterations;
}

} // namespace ibvalve::fluid
