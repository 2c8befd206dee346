#pragma once
// The `structure.volumetric_integration` setting shared by the models with a finite-element structure
// (aortic-valve, ibfe): how a body part's Material (law + volumetric penalty) is split over the
// quadrature rules of fe::SolidModel.
//   "full"     the whole Material at every point of the Gauss rule (structure.quadrature_degree);
//   "reduced"  selective reduced integration: the law on the Gauss rule, the penalty U(J) once per
//              element at its mean deformation gradient (the centre point on parallelepipeds) —
//              the cure for volumetric locking of trilinear hexes in bending (Malkus & Hughes 1978;
//              Hughes 1980; see fe/solid.hpp and docs/fe.md).
#include <memory>
#include <string>
#include <vector>

#include "fe/solid.hpp"
#include "io/config.hpp"
#include "io/key_binder.hpp"
#include "materials/material.hpp"
#include "materials/settings.hpp"

namespace ibvalve::app {

enum class VolumetricIntegration { full, reduced };

/// Adds "structure.volumetric_integration" with choices "full" and "reduced" and the given default.
void add_volumetric_integration_key(io::Schema& schema, VolumetricIntegration default_value);
/// Reads it from a validated case.
VolumetricIntegration read_volumetric_integration(const io::Config& config);
std::string volumetric_integration_name(VolumetricIntegration integration);

/// A body part of one Material: full -> the Material in `laws`; reduced -> its law in `laws` and its
/// penalty (when it has one) in `centre_laws`.
fe::BodyPart material_part(std::string name, std::vector<int> elements,
                           const std::shared_ptr<const materials::Material>& material,
                           VolumetricIntegration integration);

/// materials::material_settings for a body part with `fiber_families` fiber families (0, 1 or 2): an
/// expression law reading fibers the part lacks is an input error; its warnings (loss of convexity) are
/// logged.
materials::MaterialSettings part_material(const io::KeyBinder& keys, const materials::MaterialKeys& k,
                                          int fiber_families);

} // namespace ibvalve::app
