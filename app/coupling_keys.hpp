#pragma once
// The IB coupling's keys that every model with an immersed structure has, written once: ib.kernel and
// ib.point_spacing (ib/ibfe.hpp).
#include "ib/ibfe.hpp"
#include "io/key_binder.hpp"

namespace ibvalve::app {

/// Binds ib.kernel and ib.point_spacing to `ib` (io/key_binder.hpp).
void bind_coupling_keys(io::KeyBinder& keys, ib::IbfeSettings& ib);

} // namespace ibvalve::app
