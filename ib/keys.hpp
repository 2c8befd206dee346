#pragma once
// The IB coupling's case-file keys (io/key_binder.hpp), under "ib.": the kernel and the coupling points'
// spacing, which every model with an immersed structure has; the L2 projections of the velocity and the
// forces; the tethers ([[ib.tether]]), each pulling a group of nodes back to its reference positions.
#include <string>
#include <vector>

#include "ib/ibfe.hpp"
#include "io/key_binder.hpp"

namespace ibvalve::ib {

/// Binds <prefix>.kernel, <prefix>.point_spacing, <prefix>.coupling and <prefix>.implicit_tolerance to
/// `settings`; the spacing defaults to `default_point_spacing` grid cells, the model's (its structure's
/// elements against its grid).
void bind(io::KeyBinder& keys, IbfeSettings& settings, double default_point_spacing,
          const std::string& prefix = "ib");

/// Binds <prefix>.velocity_projection and <prefix>.force_projection (consistent or lumped) to `settings`.
void bind_projections(io::KeyBinder& keys, IbfeSettings& settings, const std::string& prefix = "ib");

/// Binds the table list [[<prefix>.tether]] to `tethers`, each element's group, stiffness and damping; the
/// groups are the mesh's to check.
void bind_tethers(io::KeyBinder& keys, std::vector<Tether>& tethers, const std::string& prefix = "ib");

} // namespace ibvalve::ib
