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

void add_schema(io::Schema& schema, const std::string& prefix)
{
  std::vector<std::string> presets = preset_names();
  presets.insert(presets.begin(), "none");
  schema.add_string(prefix + ".preset", "named Windkessel parameters; the keys below override them")
      .defaults(std::string("stergiopulos-typeA"))
      .choices(presets);
  // A key left out takes the preset's value (config.toml writes it out, naming the preset).
  auto from_preset = [](double WindkesselParameters::*member) {
    return [member](const std::string& name) -> std::optional<io::Value> {
      const auto p = preset(name);
      if (!p) return std::nullopt;
      return (*p).*member;
    };
  };
  const std::string preset_key = prefix + ".preset";
  schema.add_real(prefix + ".proximal_resistance", "R_c, proximal (characteristic) resistance")
      .unit("mmHg s/mL")
      .non_negative()
      .preset(preset_key, from_preset(&WindkesselParameters::proximal_resistance));
  schema.add_real(prefix + ".distal_resistance", "R_p, distal (peripheral) resistance")
      .unit("mmHg s/mL")
      .positive()
      .preset(preset_key, from_preset(&WindkesselParameters::distal_resistance));
  schema.add_real(prefix + ".compliance", "C, compliance")
      .unit("mL/mmHg")
      .positive()
      .preset(preset_key, from_preset(&WindkesselParameters::compliance));
  schema.add_real(prefix + ".distal_pressure", "P_d, distal (venous) pressure")
      .unit("mmHg")
      .typical(-10.0, 50.0, "venous pressure is 0 to 20 mmHg; 133 times more is a value in Pa")
      .preset(preset_key, from_preset(&WindkesselParameters::distal_pressure));
  schema.add_real(prefix + ".initial_pressure", "P_Wk(0), initial reservoir pressure")
      .unit("mmHg")
      .typical(0.0, 250.0, "arterial pressure is 60 to 140 mmHg; 133 times more is a value in Pa")
      .preset(preset_key, from_preset(&WindkesselParameters::initial_pressure));
}

WindkesselParameters parameters_from_config(const io::Config& config, const std::string& prefix)
{
  const std::string name = config.string(prefix + ".preset");
  const std::optional<WindkesselParameters> base = preset(name);
  WindkesselParameters p = base.value_or(WindkesselParameters{});
  auto read = [&](const char* key, double& value) {
    const std::string full = prefix + "." + key;
    if (config.has(full))
      value = config.real(full);
    else if (!base)
      config.fail(full, "missing (no preset given: set " + prefix + ".preset or this key)");
  };
  read("proximal_resistance", p.proximal_resistance);
  read("distal_resistance", p.distal_resistance);
  read("compliance", p.compliance);
  read("distal_pressure", p.distal_pressure);
  read("initial_pressure", p.initial_pressure);
  return p;
}

} // namespace ibvalve::windkessel
