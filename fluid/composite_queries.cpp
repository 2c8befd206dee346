#include "fluid/composite_queries.hpp"

#include <cmath>
#include <stdexcept>

#include "io/petsc_check.hpp"

namespace ibvalve::fluid {

double composite_flux(const CompositeOperators& operators, Vec u, const PlaneRegion& region)
{
  const GridHierarchy& h = operators.cells().hierarchy();
  const int a = region.normal, b = (a + 1) % 3, c = (a + 2) % 3;
  const double s = (region.position - h.domain().lower[a]) / h.h(0, a);
  if (std::abs(s - std::round(s)) > 1e-9 * std::max(1.0, std::abs(s)))
    throw std::invalid_argument("composite_flux: the plane is not a face plane of level 0");
  const double tolerance = 1e-9 * h.h(h.finest(), a);
  const PetscScalar* values = nullptr;
  PETSC_CHECK(VecGetArrayRead(u, &values));
  double flux = 0.0;
  const auto& faces = operators.owned_faces();
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const CompositeFace& face = faces[f];
    if (face.normal != a || std::abs(face.center[a] - region.position) > tolerance) continue;
    const double hb = h.h(face.level, b), hc = h.h(face.level, c);
    const double fraction = region.covered_fraction(face.center[b] - 0.5 * hb, face.center[b] + 0.5 * hb,
                                                    face.center[c] - 0.5 * hc, face.center[c] + 0.5 * hc);
    flux += fraction * face.area * values[f];
  }
  PETSC_CHECK(VecRestoreArrayRead(u, &values));
  double total = 0.0;
  MPI_Allreduce(&flux, &total, 1, MPI_DOUBLE, MPI_SUM, operators.comm());
  return total;
}

} // namespace ibvalve::fluid
