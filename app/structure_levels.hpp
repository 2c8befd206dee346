#pragma once
// Nested grid levels placed around an immersed structure (docs/nested.md, "IB on the finest level"): the
// ibfe and aortic-valve models put the structure on the finest level, which must be one box holding the
// structure's starting configuration with room for the kernel's reach.
#include <span>
#include <string>

#include "app/resource_estimate.hpp"
#include "fe/mesh.hpp"
#include "fluid/hierarchy.hpp"
#include "ib/kernels.hpp"
#include "io/key_binder.hpp"

namespace ibvalve::app {

/// The nested fluid's part of the memory estimate: the cells of every level of `hierarchy`, blamed on
/// `ratios_key` (nested.ratios) when the finer levels more than double the cells of `box`, else on
/// `cells_key`.
MemoryPart nested_fluid_memory(const fluid::GridHierarchy& hierarchy, const fluid::BoxGeometry& box,
                               const std::string& cells_key, const std::string& ratios_key);

/// The nested levels of a case whose structure starts at `positions` (node positions): read_hierarchy with
/// the structure's bounding box and the reach of `kernel`, automatic levels placed around it;
/// `structure_key` names the structure in the error when explicit boxes miss it. InputError (nested.box)
/// unless the finest level is one box (the structure lives on it).
fluid::GridHierarchy read_structure_levels(const io::KeyBinder& keys, const fluid::NestedKeys& k,
                                           const fluid::BoxGeometry& box, std::span<const fe::Vec3> positions,
                                           ib::KernelKind kernel, const std::string& structure_key);

} // namespace ibvalve::app
