#include "drivers/windkessel_driver.hpp"

#include <fmt/format.h>

#include "base/units.hpp"

namespace ibvalve::drivers {

WindkesselDriver::WindkesselDriver(Side side, const windkessel::WindkesselParameters& parameters)
    : BoundaryDriver(side), windkessel_(parameters)
{
}

void WindkesselDriver::advance(double, double dt, double flow)
{
  // Downstream the flow through the side enters the Windkessel; upstream it leaves it.
  windkessel_.advance(dt, side() == Side::downstream ? flow : -flow);
}

std::vector<Column> WindkesselDriver::columns() const
{
  if (side() == Side::downstream) return {}; // the report's own P_Wk
  return {{"P_Wk_upstream", "mmHg"}};
}

std::vector<double> WindkesselDriver::row(double) const
{
  if (side() == Side::downstream) return {};
  return {windkessel_.reservoir_pressure() / units::mmHg};
}

void WindkesselDriver::save(io::Hdf5File& h5, const std::string& group) const
{
  const windkessel::WindkesselState& s = windkessel_.state();
  save_number(h5, group, "time", s.time);
  save_number(h5, group, "P_Wk", s.reservoir_pressure);
  save_number(h5, group, "Q", s.flow);
}

void WindkesselDriver::restore(const io::Hdf5File& h5, const std::string& group)
{
  windkessel_.restore(
      {read_number(h5, group, "time"), read_number(h5, group, "P_Wk"), read_number(h5, group, "Q")});
}

std::string WindkesselDriver::describe() const
{
  const windkessel::WindkesselParameters& p = windkessel_.parameters();
  const double resistance = units::mmHg / units::mL;
  return fmt::format(
      "{} three-element Windkessel: R_c {:g}, R_p {:g} mmHg s/mL, C {:g} mL/mmHg, P_Wk(0) {:g} mmHg",
      side_name(side()), p.proximal_resistance / resistance, p.distal_resistance / resistance,
      p.compliance / (units::mL / units::mmHg), p.initial_pressure / units::mmHg);
}

} // namespace ibvalve::drivers
