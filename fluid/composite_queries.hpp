#pragma once
// Queries across nested levels (docs/nested.md): the volume flux of a composite face field through a
// rectangle or disk (fluid/queries.hpp's PlaneRegion) on a plane that crosses levels.
#include "fluid/composite_poisson.hpp"
#include "fluid/queries.hpp"

namespace ibvalve::fluid {

/// int u.n dA over `region` from the composite normal-velocity face vector `u`: each composite face on the
/// region's plane adds (its area inside the region) x u_f, so the finest data is used wherever it exists.
/// The plane must be a face plane of level 0 (then it is one of every level); otherwise
/// std::invalid_argument. Collective; the same value on every rank.
double composite_flux(const CompositeOperators& operators, Vec u, const PlaneRegion& region);

} // namespace ibvalve::fluid
