#pragma once
// The fluid box every grid-based run model reads from its case file: fluid.cells, fluid.lower and
// fluid.upper (at least 4 cells per direction, upper above lower). Periodicity is each model's own.
#include "app/resource_estimate.hpp"
#include "fluid/grid.hpp"
#include "fluid/settings.hpp"
#include "io/config.hpp"
#include "io/key_binder.hpp"

namespace ibvalve::app {

/// The box of the bound keys `cells`, `lower` and `upper` (read by `keys`): at least 4 cells a direction,
/// upper above lower; also refuses a grid whose unknowns PETSc's index type cannot count.
fluid::BoxGeometry fluid_box(const io::KeyBinder& keys, const std::vector<std::int64_t>& cells,
                             const std::vector<double>& lower, const std::vector<double>& upper);

/// The box's cells, in floating point (no product of counts can wrap).
double grid_cells(const fluid::BoxGeometry& box);
/// The one-grid solver `settings` chooses, as far as memory goes.
FluidMemoryKind memory_kind(const fluid::FluidSettings& settings);

} // namespace ibvalve::app
