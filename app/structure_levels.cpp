#include "app/structure_levels.hpp"

#include <algorithm>

#include "app/fluid_box.hpp"
#include "ib/kernels.hpp"

namespace ibvalve::app {

MemoryPart nested_fluid_memory(const fluid::GridHierarchy& hierarchy, const fluid::BoxGeometry& box,
                               const std::string& cells_key, const std::string& ratios_key)
{
  double cells = 1.0;
  for (int d = 0; d < 3; ++d) cells *= static_cast<double>(hierarchy.domain_cells(0)[d]);
  for (int level = 1; level < hierarchy.levels(); ++level)
    for (const fluid::IndexBox& level_box : hierarchy.boxes(level))
      cells += static_cast<double>(level_box.cells(0)) * static_cast<double>(level_box.cells(1)) *
               static_cast<double>(level_box.cells(2));
  return fluid_memory(cells, FluidMemoryKind::nested, true,
                      cells > 2.0 * grid_cells(box) ? ratios_key : cells_key);
}

fluid::GridHierarchy read_structure_levels(const io::KeyBinder& keys, const fluid::NestedKeys& k,
                                           const fluid::BoxGeometry& box, std::span<const fe::Vec3> positions,
                                           ib::KernelKind kernel, const std::string& structure_key)
{
  fluid::PhysicalBox bounds;
  for (int d = 0; d < 3; ++d) {
    bounds.lower[d] = 1e300;
    bounds.upper[d] = -1e300;
  }
  for (const fe::Vec3& x : positions)
    for (int d = 0; d < 3; ++d) {
      bounds.lower[d] = std::min(bounds.lower[d], x[d]);
      bounds.upper[d] = std::max(bounds.upper[d], x[d]);
    }
  const int reach = (ib::DeltaKernel(kernel).support() + 1) / 2;
  fluid::GridHierarchy hierarchy = fluid::read_hierarchy(keys, k, box, bounds, structure_key, reach);
  if (hierarchy.boxes(hierarchy.finest()).size() != 1)
    keys.fail(k.boxes, "the finest level must be one box: the structure lives on it");
  return hierarchy;
}

} // namespace ibvalve::app
