#pragma once
// A body part's material as the models with a finite-element structure (aortic-valve, ibfe) read it: the
// table's law resolved (materials/settings.hpp), checked against the part's fiber families, its warnings
// logged. How the part's material is integrated is fe/volumetric_integration.hpp's.
#include "io/key_binder.hpp"
#include "materials/settings.hpp"

namespace ibvalve::app {

/// materials::material_settings for a body part with `fiber_families` fiber families (0, 1 or 2): an
/// expression law reading fibers the part lacks is an input error; its warnings (loss of convexity) are
/// logged.
materials::MaterialSettings part_material(const io::KeyBinder& keys, const materials::MaterialKeys& k,
                                          int fiber_families);

} // namespace ibvalve::app
