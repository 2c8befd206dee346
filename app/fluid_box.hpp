#pragma once
// The fluid box every grid-based run model reads from its case file: fluid.cells, fluid.lower and
// fluid.upper (at least 4 cells per direction, upper above lower). Periodicity is each model's own.
#include "app/resource_estimate.hpp"
#include "fluid/grid.hpp"
#include "fluid/navier_stokes.hpp"
#include "io/config.hpp"

namespace ibvalve::app {

/// Also refuses, naming fluid.cells, a grid whose unknowns PETSc's index type cannot count.
fluid::BoxGeometry read_fluid_box(const io::Config& config);

/// The box's cells, in floating point (no product of counts can wrap).
double grid_cells(const fluid::BoxGeometry& box);
/// The one-grid solver `settings` chooses, as far as memory goes.
FluidMemoryKind memory_kind(const fluid::FluidSettings& settings);

} // namespace ibvalve::app
