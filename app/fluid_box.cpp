#include "app/fluid_box.hpp"

namespace ibvalve::app {

fluid::BoxGeometry fluid_box(const io::KeyBinder& keys, const std::vector<std::int64_t>& cells,
                             const std::vector<double>& lower, const std::vector<double>& upper)
{
  fluid::BoxGeometry box;
  for (int d = 0; d < 3; ++d) {
    box.cells[d] = static_cast<PetscInt>(cells[d]);
    box.lower[d] = lower[d];
    box.upper[d] = upper[d];
    if (box.cells[d] < 4) keys.fail(cells, "needs at least 4 cells per direction");
    if (!(box.upper[d] > box.lower[d]))
      keys.fail(upper, "must lie above " + keys.key_of(lower) + " in every direction");
  }
  // Three velocity components on the faces and the pressure in the cells: about 4 (n+1)^3 unknowns.
  double unknowns = 4.0;
  for (int d = 0; d < 3; ++d) unknowns *= static_cast<double>(cells[d]) + 1.0;
  check_index_count(keys.config(), keys.key_of(cells), unknowns, "grid unknowns");
  return box;
}

double grid_cells(const fluid::BoxGeometry& box)
{
  return static_cast<double>(box.cells[0]) * static_cast<double>(box.cells[1]) *
         static_cast<double>(box.cells[2]);
}

FluidMemoryKind memory_kind(const fluid::FluidSettings& settings)
{
  if (settings.solver == fluid::SolverKind::fft) return FluidMemoryKind::fft;
  return settings.subsolver == fluid::SubsolverKind::fft ? FluidMemoryKind::krylov_fft
                                                         : FluidMemoryKind::krylov_amg;
}

} // namespace ibvalve::app
