#include "fe/volumetric_integration.hpp"

#include <utility>

namespace ibvalve::fe {

void bind(io::KeyBinder& keys, VolumetricIntegration& integration, VolumetricIntegration default_value,
          const std::string& prefix)
{
  keys.choice(prefix + ".volumetric_integration",
              "how the volumetric penalty U(J) is integrated: \"full\" = with the law on the Gauss "
              "rule of structure.quadrature_degree; \"reduced\" = once per element at its mean "
              "deformation gradient (selective reduced integration; cures the volumetric locking of "
              "trilinear hexes in bending)",
              integration,
              {{"full", VolumetricIntegration::full}, {"reduced", VolumetricIntegration::reduced}})
      .defaults(std::string(default_value == VolumetricIntegration::reduced ? "reduced" : "full"));
}

BodyPart material_part(std::string name, std::vector<int> elements,
                       const std::shared_ptr<const materials::Material>& material,
                       VolumetricIntegration integration)
{
  BodyPart part{std::move(name), std::move(elements), {}};
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

} // namespace ibvalve::fe
