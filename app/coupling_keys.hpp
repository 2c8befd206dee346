#pragma once
// The IB coupling's keys that every model with an immersed structure has, written once: ib.kernel and
// ib.point_spacing (ib/ibfe.hpp).
#include "ib/ibfe.hpp"
#include "io/key_binder.hpp"

namespace ibvalve::app {

/// Binds ib.kernel and ib.point_spacing to `ib` (io/key_binder.hpp); the spacing defaults to
/// `default_point_spacing` grid cells, the model's (its structure's elements against its grid).
void bind_coupling_keys(io::KeyBinder& keys, ib::IbfeSettings& ib, double default_point_spacing);

} // namespace ibvalve::app
