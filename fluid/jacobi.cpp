#include "fluid/jacobi.hpp"

#include <algorithm>
#include <cmath>

#include "io/petsc_check.hpp"

namespace ibvalve::fluid {

double jacobi_ratio(Mat a)
{
  PetscInt begin = 0, end = 0;
  PETSC_CHECK(MatGetOwnershipRange(a, &begin, &end));
  double ratio = 0.0;
  for (PetscInt row = begin; row < end; ++row) {
    PetscInt count = 0;
    const PetscInt* columns = nullptr;
    const PetscScalar* values = nullptr;
    PETSC_CHECK(MatGetRow(a, row, &count, &columns, &values));
    double diagonal = 0.0, off = 0.0;
    for (PetscInt k = 0; k < count; ++k) (columns[k] == row ? diagonal : off) += std::abs(values[k]);
    PETSC_CHECK(MatRestoreRow(a, row, &count, &columns, &values));
    ratio = std::max(ratio, diagonal > 0.0 ? off / diagonal : 1e300);
  }
  PETSC_CHECK(MPI_Allreduce(MPI_IN_PLACE, &ratio, 1, MPI_DOUBLE, MPI_MAX,
                            PetscObjectComm(reinterpret_cast<PetscObject>(a))));
  return ratio;
}

} // namespace ibvalve::fluid
