#include "app/fluid_box.hpp"

namespace ibvalve::app {

fluid::BoxGeometry read_fluid_box(const io::Config& config)
{
  fluid::BoxGeometry box;
  const auto cells = config.integers("fluid.cells");
  const auto lower = config.reals("fluid.lower");
  const auto upper = config.reals("fluid.upper");
  for (int d = 0; d < 3; ++d) {
    box.cells[d] = static_cast<PetscInt>(cells[d]);
    box.lower[d] = lower[d];
    box.upper[d] = upper[d];
    if (box.cells[d] < 4) config.fail("fluid.cells", "needs at least 4 cells per direction");
    if (!(box.upper[d] > box.lower[d]))
      config.fail("fluid.upper", "must lie above fluid.lower in every direction");
  }
  return box;
}

} // namespace ibvalve::app
