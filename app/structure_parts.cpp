#include "app/structure_parts.hpp"

#include <string>

#include "base/logger.hpp"

namespace ibvalve::app {

materials::MaterialSettings part_material(const io::KeyBinder& keys, const materials::MaterialKeys& k,
                                          int fiber_families)
{
  materials::MaterialSettings material = materials::material_settings(keys, k);
  materials::check_fiber_families(material, fiber_families, keys, k);
  for (const std::string& warning : material.warnings) base::Logger::global().warn(warning);
  return material;
}

} // namespace ibvalve::app
