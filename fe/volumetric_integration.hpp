#pragma once
// How a body part's Material (law + volumetric penalty) is split over the quadrature rules of
// fe::SolidModel (fe/solid.hpp), and the case-file key that chooses it, structure.volumetric_integration:
//   "full"     the whole Material at every point of the Gauss rule (structure.quadrature_degree);
//   "reduced"  selective reduced integration: the law on the Gauss rule, the penalty U(J) once per
//              element at its mean deformation gradient (the centre point on parallelepipeds) —
//              the cure for volumetric locking of trilinear hexes in bending (Malkus & Hughes 1978;
//              Hughes 1980; docs/fe.md).
#include <memory>
#include <string>
#include <vector>

#include "fe/solid.hpp"
#include "io/key_binder.hpp"
#include "materials/material.hpp"

namespace ibvalve::fe {

enum class VolumetricIntegration { full, reduced };

/// Declares or reads `<prefix>.volumetric_integration` (io/key_binder.hpp), "full" or "reduced", into
/// `integration`; `default_value` is the model's.
void bind(io::KeyBinder& keys, VolumetricIntegration& integration, VolumetricIntegration default_value,
          const std::string& prefix = "structure");

/// A body part of one Material: full -> the Material in `laws`; reduced -> its law in `laws` and its
/// penalty (when it has one) in `centre_laws`.
BodyPart material_part(std::string name, std::vector<int> elements,
                       const std::shared_ptr<const materials::Material>& material,
                       VolumetricIntegration integration);

} // namespace ibvalve::fe
