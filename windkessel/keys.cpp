#include "windkessel/keys.hpp"

#include <optional>
#include <vector>

namespace ibvalve::windkessel {

void bind(io::KeyBinder& keys, WindkesselKeys& k, const std::string& prefix)
{
  std::vector<std::string> presets = preset_names();
  presets.insert(presets.begin(), "none");
  const std::string preset_key = prefix + ".preset";
  keys.string(preset_key, "named Windkessel parameters; the keys below override them", k.preset)
      .defaults(std::string("stergiopulos-typeA"))
      .choices(presets);
  const std::optional<WindkesselParameters> base = keys.reading() ? preset(k.preset) : std::nullopt;
  WindkesselParameters& p = k.parameters;
  if (keys.reading()) p = base.value_or(WindkesselParameters{}); // then each key given replaces its value
  // A key left out takes the preset's value (config.toml writes it out, naming the preset).
  auto from_preset = [](double WindkesselParameters::*member) {
    return [member](const std::string& name) -> std::optional<io::Value> {
      const auto q = preset(name);
      if (!q) return std::nullopt;
      return (*q).*member;
    };
  };
  using W = WindkesselParameters;
  keys.real(prefix + ".proximal_resistance", "R_c, proximal (characteristic) resistance",
            p.proximal_resistance)
      .unit("mmHg s/mL")
      .non_negative()
      .preset(preset_key, from_preset(&W::proximal_resistance));
  keys.real(prefix + ".distal_resistance", "R_p, distal (peripheral) resistance", p.distal_resistance)
      .unit("mmHg s/mL")
      .positive()
      .preset(preset_key, from_preset(&W::distal_resistance));
  keys.real(prefix + ".compliance", "C, compliance", p.compliance)
      .unit("mL/mmHg")
      .positive()
      .preset(preset_key, from_preset(&W::compliance));
  keys.real(prefix + ".distal_pressure", "P_d, distal (venous) pressure", p.distal_pressure)
      .unit("mmHg")
      .typical(-10.0, 50.0, "venous pressure is 0 to 20 mmHg; 133 times more is a value in Pa")
      .preset(preset_key, from_preset(&W::distal_pressure));
  keys.real(prefix + ".initial_pressure", "P_Wk(0), initial reservoir pressure", p.initial_pressure)
      .unit("mmHg")
      .typical(0.0, 250.0, "arterial pressure is 60 to 140 mmHg; 133 times more is a value in Pa")
      .preset(preset_key, from_preset(&W::initial_pressure));
}

void check(const io::KeyBinder& keys, const WindkesselKeys& k)
{
  if (preset(k.preset)) return;
  const WindkesselParameters& p = k.parameters;
  for (const double* value :
       {&p.proximal_resistance, &p.distal_resistance, &p.compliance, &p.distal_pressure, &p.initial_pressure})
    if (!keys.has(*value))
      keys.fail(*value, "missing (no preset given: set " + keys.key_of(k.preset) + " or this key)");
}

void bind(io::KeyBinder& keys, WaveformKeys& k, const std::string& prefix, const std::string& doc,
          bool file_required)
{
  io::KeyBuilder file =
      keys.path(prefix + ".file",
                doc + ": CSV table with a header, one period, last row = first row one period later", k.file);
  if (file_required) file.required();
  file.example(std::string("lv_pressure_typeA.csv"));
  keys.string(prefix + ".time_column", "the table's time column (s)", k.time_column)
      .defaults(std::string("time"));
  keys.string(prefix + ".value_column", "the table's value column", k.value_column)
      .defaults(std::string("pressure"));
  keys.choice(prefix + ".interpolation", "between table points", k.interpolation,
              {{"linear", Interpolation::linear}, {"monotone-cubic", Interpolation::monotone_cubic}})
      .defaults(std::string("monotone-cubic"));
}

PeriodicWaveform load_waveform(const WaveformKeys& k, double value_factor)
{
  return PeriodicWaveform::from_csv(k.file, k.time_column, k.value_column, value_factor, k.interpolation);
}

} // namespace ibvalve::windkessel
