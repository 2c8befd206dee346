#include "windkessel/windkessel.hpp"

#include <cmath>
#include <stdexcept>

#include "base/errors.hpp"
#include "base/units.hpp"

namespace ibvalve::windkessel {

void WindkesselParameters::check() const
{
  if (!(proximal_resistance >= 0.0)) throw std::invalid_argument("Windkessel: R_c must be >= 0");
  if (!(distal_resistance > 0.0)) throw std::invalid_argument("Windkessel: R_p must be > 0");
  if (!(compliance > 0.0)) throw std::invalid_argument("Windkessel: C must be > 0");
}

std::optional<WindkesselParameters> preset(std::string_view name)
{
  // Values in the units a case file writes, converted as a written value is (io::Config::real), so a
  // run folder's config.toml, which writes them out, reads back to exactly these.
  const double resistance = *units::to_cgs("mmHg s/mL"), compliance = *units::to_cgs("mL/mmHg");
  const double pressure = *units::to_cgs("mmHg");
  if (name == "stergiopulos-typeA") {
    WindkesselParameters p;
    p.proximal_resistance = 0.033 * resistance;
    p.distal_resistance = 0.79 * resistance;
    p.compliance = 1.75 * compliance;
    p.distal_pressure = 0.0 * pressure;
    p.initial_pressure = 85.0 * pressure;
    return p;
  }
  return std::nullopt;
}

std::vector<std::string> preset_names()
{
  return {"stergiopulos-typeA"};
}

ThreeElementWindkessel::ThreeElementWindkessel(const WindkesselParameters& parameters, double start_time,
                                               double start_flow)
    : parameters_(parameters)
{
  parameters_.check();
  state_.time = start_time;
  state_.reservoir_pressure = parameters_.initial_pressure;
  state_.flow = start_flow;
}

namespace {
/// 1 - (1 - e^{-x}) / x, the weight of the flow's change over a step, without cancellation for small x.
double ramp_weight(double x)
{
  if (x < 1.0e-2) return x * (0.5 - x * (1.0 / 6.0 - x * (1.0 / 24.0 - x * (1.0 / 120.0 - x / 720.0))));
  return 1.0 + std::expm1(-x) / x;
}
} // namespace

double ThreeElementWindkessel::reservoir_pressure_after(double dt, double flow_start, double flow_end) const
{
  if (!(dt >= 0.0)) throw std::invalid_argument("Windkessel: negative time step");
  // y = P_Wk - P_d obeys dy/dt = -y/tau + Q/C with tau = R_p C. For Q(s) = Q0 + (Q1 - Q0) s/dt the
  // variation-of-constants integral is exact:
  //   y(dt) = y0 e^{-x} + R_p [Q0 (1 - e^{-x}) + (Q1 - Q0) (1 - (1 - e^{-x})/x)],  x = dt/tau.
  const double x = dt / parameters_.time_constant();
  const double decay = std::exp(-x);
  const double y0 = state_.reservoir_pressure - parameters_.distal_pressure;
  const double y1 = y0 * decay + parameters_.distal_resistance * (flow_start * -std::expm1(-x) +
                                                                  (flow_end - flow_start) * ramp_weight(x));
  return parameters_.distal_pressure + y1;
}

double ThreeElementWindkessel::advance(double dt, double flow_start, double flow_end)
{
  state_.reservoir_pressure = reservoir_pressure_after(dt, flow_start, flow_end);
  state_.time += dt;
  state_.flow = flow_end;
  return outlet_pressure();
}

double ThreeElementWindkessel::reservoir_rate(double reservoir_pressure, double flow) const
{
  return (flow - (reservoir_pressure - parameters_.distal_pressure) / parameters_.distal_resistance) /
         parameters_.compliance;
}

} // namespace ibvalve::windkessel
