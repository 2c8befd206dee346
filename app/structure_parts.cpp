#include "app/structure_parts.hpp"

#include <utility>

#include "base/logger.hpp"

namespace ibvalve::app {

void add_volumetric_integration_key(io::Schema& schema, VolumetricIntegration default_value)
{
  schema
      .add_string("structure.volumetric_integration",
                  "how the volumetric penalty U(J) is integrated: \"full\" = with the law on the Gauss "
                  "rule of structure.quadrature_degree; \"reduced\" = once per element at its mean "
                  "deformation gradient (selective reduced integration; cures the volumetric locking of "
                  "trilinear hexes in bending)")
      .defaults(volumetric_integration_name(default_value))
      .choices({"full", "reduced"});
}

VolumetricIntegration read_volumetric_integration(const io::Config& config)
{
  return config.string("structure.volumetric_integration") == "reduced" ? VolumetricIntegration::reduced
                                                                        : VolumetricIntegration::full;
}

std::string volumetric_integration_name(VolumetricIntegration integration)
{
  return integration == VolumetricIntegration::reduced ? "reduced" : "full";
}

fe::BodyPart material_part(std::string name, std::vector<int> elements,
                           const std::shared_ptr<const materials::Material>& material,
                           VolumetricIntegration integration)
{
  fe::BodyPart part{std::move(name), std::move(elements), {}};
  if (integration == VolumetricIntegration::full ||
      material->penalty().kind() == materials::PenaltyKind::none) {
    part.laws.push_back(material);
    return part;
  }
  // Aliasing shared_ptrs: they point at the Material's law and penalty and keep the Material alive.
  part.laws.emplace_back(material, &material->law());
  part.centre_laws.emplace_back(material, &material->penalty());
  return part;
}

materials::MaterialSettings part_material(const io::KeyBinder& keys, const materials::MaterialKeys& k,
                                          int fiber_families)
{
  materials::MaterialSettings material = materials::material_settings(keys, k);
  materials::check_fiber_families(material, fiber_families, keys, k);
  for (const std::string& warning : material.warnings) base::Logger::global().warn(warning);
  return material;
}

} // namespace ibvalve::app
