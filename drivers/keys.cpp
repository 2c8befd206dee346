#include "drivers/keys.hpp"

#include <memory>

#include "base/units.hpp"
#include "drivers/table_driver.hpp"
#include "drivers/windkessel_driver.hpp"

namespace ibvalve::drivers {

namespace {

// The loop settles on its own at T/8000 a step, as examples/lumped/closed_loop.toml runs it.
constexpr long settle_steps_per_beat = 8000;

std::shared_ptr<ClosedLoopCoupling> make_loop(const io::KeyBinder& keys, const DriverKeys& k)
{
  if (keys.has(k.lv_pressure.file))
    keys.fail(k.lv_pressure.file, "not used with " + keys.key_of(k.sides.inlet) +
                                      " = \"circulation\" (the loop's ventricle gives the inlet pressure)");
  circulation::check(keys, k.circulation);
  if (k.circulation.parameters.aortic_kind != circulation::AorticValveKind::diode)
    keys.fail(k.circulation.parameters.aortic_kind,
              "must be \"diode\" here: the 3-D valve is the loop's aortic valve (the diode serves only the "
              "beats before t = 0, " +
                  keys.key_of(k.start_beats) + ")");
  return std::make_shared<ClosedLoopCoupling>(k.circulation.parameters, static_cast<int>(k.start_beats),
                                              settle_steps_per_beat);
}

} // namespace

void bind(io::KeyBinder& keys, DriverSides& k)
{
  keys.choice("inlet.driver",
              "what drives the inlet: the LV pressure table of lv_pressure.* (the study), or the closed-loop "
              "circulation's left ventricle (circulation.*; the outlet's driver must then be the loop too)",
              k.inlet, {{"table", InletKind::table}, {"circulation", InletKind::circulation}})
      .defaults(std::string("table"));
  keys.choice("outlet.driver",
              "what loads the outlet: the three-element Windkessel of windkessel.* (the study), or the "
              "closed-loop circulation's systemic arteries",
              k.outlet, {{"windkessel", OutletKind::windkessel}, {"circulation", OutletKind::circulation}})
      .defaults(std::string("windkessel"));
}

bool closed_loop(const io::KeyBinder& keys, const DriverSides& sides)
{
  const bool inlet = sides.inlet == InletKind::circulation, outlet = sides.outlet == OutletKind::circulation;
  if (inlet && !outlet)
    keys.fail(sides.outlet,
              "must be \"circulation\" with " + keys.key_of(sides.inlet) +
                  " = \"circulation\": the loop's systemic arteries take what its ventricle ejects");
  if (outlet && !inlet)
    keys.fail(sides.inlet, "must be \"circulation\" with " + keys.key_of(sides.outlet) +
                               " = \"circulation\": the loop's ventricle feeds its systemic arteries");
  return inlet;
}

void bind(io::KeyBinder& keys, DriverKeys& k)
{
  bind(keys, k.sides);
  keys.integer("circulation.start_beats",
               "beats the closed loop runs on its own (its diode aortic valve) before the 3-D valve joins "
               "it at t = 0, from the preset's initial state",
               k.start_beats)
      .defaults(std::int64_t{60})
      .at_least(0)
      .at_most(1000);
  circulation::bind(keys, k.circulation);
}

BoundaryDrivers make_drivers(const io::KeyBinder& keys, const DriverKeys& k)
{
  if (closed_loop(keys, k.sides)) {
    std::shared_ptr<ClosedLoopCoupling> loop = make_loop(keys, k);
    return BoundaryDrivers(std::make_unique<ClosedLoopSide>(Side::upstream, loop),
                           std::make_unique<ClosedLoopSide>(Side::downstream, loop), loop);
  }
  if (!keys.has(k.lv_pressure.file))
    keys.fail(k.lv_pressure.file, "missing: " + keys.key_of(k.sides.inlet) +
                                      " = \"table\" needs the LV pressure table (a CSV file)");
  auto table = std::make_unique<TableDriver>(
      Side::upstream, windkessel::load_waveform(k.lv_pressure, units::mmHg), "LV pressure table");
  windkessel::check(keys, k.windkessel);
  auto outlet = std::make_unique<WindkesselDriver>(Side::downstream, k.windkessel.parameters);
  return BoundaryDrivers(std::move(table), std::move(outlet));
}

} // namespace ibvalve::drivers
