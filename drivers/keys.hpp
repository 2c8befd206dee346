#pragma once
// The valve cases' choice of drivers (io/key_binder.hpp) and the drivers the 3-D valve builds
// (docs/drivers.md); the lumped valve makes the same choice with the same two keys:
//
//   inlet.driver  = "table" (lv_pressure.* : the prescribed LV pressure) | "circulation"
//   outlet.driver = "windkessel" (windkessel.* : the three-element Windkessel) | "circulation"
//   circulation.* (circulation/keys.hpp: the loop's parameters), circulation.start_beats
//
// "circulation" is the closed loop of circulation/, which drives both sides at once: its left
// ventricle upstream, its systemic arteries downstream.
#include <cstdint>

#include "circulation/keys.hpp"
#include "drivers/boundary_drivers.hpp"
#include "io/key_binder.hpp"
#include "windkessel/keys.hpp"

namespace ibvalve::drivers {

enum class InletKind { table, circulation };
enum class OutletKind { windkessel, circulation };

/// The choice of the two sides' drivers, which the 3-D valve and the lumped valve share.
struct DriverSides {
  InletKind inlet = InletKind::table;
  OutletKind outlet = OutletKind::windkessel;
};

struct DriverKeys {
  DriverSides sides;
  std::int64_t start_beats = 0;
  circulation::CirculationKeys circulation;
  windkessel::WaveformKeys lv_pressure; // the table's
  windkessel::WindkesselKeys windkessel;
};

/// Declares or reads inlet.driver and outlet.driver alone.
void bind(io::KeyBinder& keys, DriverSides& sides);

/// Whether the sides are the closed loop (both "circulation") rather than the table and the Windkessel
/// (neither); the loop on one side only is an InputError naming the key.
bool closed_loop(const io::KeyBinder& keys, const DriverSides& sides);

/// Declares or reads inlet.driver, outlet.driver, circulation.start_beats and the loop's circulation.*.
/// The table's lv_pressure.* and the Windkessel's windkessel.* are windkessel/'s sections
/// (windkessel/keys.hpp), which the case binds into `lv_pressure` and `windkessel` where it lists them
/// (lv_pressure.file not required: the table driver asks for it).
void bind(io::KeyBinder& keys, DriverKeys& k);

/// The drivers the keys `keys` read into `k` choose. Bad input (a loop on one side only, the table's file
/// missing or given beside the loop, a Windkessel parameter neither given nor preset, the loop's own
/// parameters) is an InputError naming the key.
BoundaryDrivers make_drivers(const io::KeyBinder& keys, const DriverKeys& k);

} // namespace ibvalve::drivers
