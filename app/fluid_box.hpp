#pragma once
// The fluid box every grid-based run model reads from its case file: fluid.cells, fluid.lower and
// fluid.upper (at least 4 cells per direction, upper above lower). Periodicity is each model's own.
#include "fluid/grid.hpp"
#include "io/config.hpp"

namespace ibvalve::app {

fluid::BoxGeometry read_fluid_box(const io::Config& config);

} // namespace ibvalve::app
