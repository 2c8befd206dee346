#include "circulation/keys.hpp"

#include <functional>

namespace ibvalve::circulation {

std::optional<CirculationParameters> preset(std::string_view name)
{
  if (name == "regazzoni2022") return regazzoni2022();
  return std::nullopt;
}

std::vector<std::string> preset_names()
{
  return {"regazzoni2022"};
}

namespace {

constexpr const char* preset_key = "circulation.preset";

/// A parameter's value in a preset, found by the same path into the struct as the bound target.
using Field = std::function<double(const CirculationParameters&)>;

/// Binds `circulation.<key>` to `target`, the preset supplying the value when the key is not given.
io::KeyBuilder bind_real(io::KeyBinder& keys, const std::string& key, std::string doc, double& target,
                         const char* unit, Field field)
{
  io::KeyBuilder builder = keys.real("circulation." + key, std::move(doc), target);
  builder.unit(unit).preset(preset_key, [field](const std::string& name) -> std::optional<io::Value> {
    const auto p = preset(name);
    if (!p) return std::nullopt;
    return field(*p);
  });
  return builder;
}

void bind_chamber(io::KeyBinder& keys, const std::string& name, ChamberParameters& c,
                  ChamberParameters CirculationParameters::*member)
{
  auto field = [member](double ChamberParameters::*f) {
    return [member, f](const CirculationParameters& p) { return (p.*member).*f; };
  };
  bind_real(keys, name + ".active_elastance", "E_A: elastance at full activation minus E_B",
            c.active_elastance, "mmHg/mL", field(&ChamberParameters::active_elastance))
      .non_negative();
  bind_real(keys, name + ".passive_elastance", "E_B: elastance at rest", c.passive_elastance, "mmHg/mL",
            field(&ChamberParameters::passive_elastance))
      .positive();
  bind_real(keys, name + ".rest_volume", "V_0: volume at zero pressure", c.rest_volume, "mL",
            field(&ChamberParameters::rest_volume))
      .non_negative();
  bind_real(keys, name + ".contraction_start", "t_C: start of the contraction, fraction of the beat",
            c.contraction_start, "1", field(&ChamberParameters::contraction_start))
      .at_least(0.0)
      .below(1.0);
  bind_real(keys, name + ".contraction_time", "T_C: duration of the contraction, fraction of the beat",
            c.contraction_time, "1", field(&ChamberParameters::contraction_time))
      .positive()
      .below(1.0);
  bind_real(keys, name + ".relaxation_time", "T_R: duration of the relaxation, fraction of the beat",
            c.relaxation_time, "1", field(&ChamberParameters::relaxation_time))
      .positive()
      .below(1.0);
}

void bind_valve(io::KeyBinder& keys, const std::string& name, DiodeValve& v,
                DiodeValve CirculationParameters::*member)
{
  bind_real(keys, name + ".open_resistance", "R_min: resistance of the open valve", v.open_resistance,
            "mmHg s/mL", [member](const CirculationParameters& p) { return (p.*member).open_resistance; })
      .positive();
  bind_real(keys, name + ".closed_resistance", "R_max: resistance of the closed valve", v.closed_resistance,
            "mmHg s/mL", [member](const CirculationParameters& p) { return (p.*member).closed_resistance; })
      .positive();
}

void bind_compartment(io::KeyBinder& keys, const std::string& name, Compartment& c,
                      Compartment CirculationParameters::*member)
{
  bind_real(keys, name + ".resistance", "R: resistance to the next compartment", c.resistance, "mmHg s/mL",
            [member](const CirculationParameters& p) { return (p.*member).resistance; })
      .positive();
  bind_real(keys, name + ".compliance", "C: compliance (volume C p)", c.compliance, "mL/mmHg",
            [member](const CirculationParameters& p) { return (p.*member).compliance; })
      .positive();
  bind_real(keys, name + ".inertance", "L: inertance to the next compartment", c.inertance, "mmHg s^2/mL",
            [member](const CirculationParameters& p) { return (p.*member).inertance; })
      .positive();
}

} // namespace

void bind(io::KeyBinder& keys, CirculationKeys& k)
{
  keys.string(preset_key, "named circulation parameters (docs/circulation.md); the keys below override them",
              k.preset)
      .defaults(std::string("regazzoni2022"))
      .choices(preset_names());
  if (keys.reading()) k.parameters = *preset(k.preset); // then each key given replaces its value
  CirculationParameters& p = k.parameters;
  bind_real(keys, "heart_rate", "heart rate; the beat T = 60 s / rate", p.heart_rate, "1/min",
            [](const CirculationParameters& q) { return q.heart_rate; })
      .positive()
      .typical(30.0, 200.0, "beats per minute");
  using P = CirculationParameters;
  bind_chamber(keys, "left_atrium", p.left_atrium, &P::left_atrium);
  bind_chamber(keys, "left_ventricle", p.left_ventricle, &P::left_ventricle);
  bind_chamber(keys, "right_atrium", p.right_atrium, &P::right_atrium);
  bind_chamber(keys, "right_ventricle", p.right_ventricle, &P::right_ventricle);
  bind_valve(keys, "mitral_valve", p.mitral, &P::mitral);
  bind_valve(keys, "aortic_valve", p.aortic, &P::aortic);
  bind_valve(keys, "tricuspid_valve", p.tricuspid, &P::tricuspid);
  bind_valve(keys, "pulmonary_valve", p.pulmonary, &P::pulmonary);
  keys.choice("circulation.aortic_valve.model",
              "the aortic valve: the preset's resistive diode, or the 0-D orifice valve of the [valve] keys",
              p.aortic_kind, {{"diode", AorticValveKind::diode}, {"orifice", AorticValveKind::orifice}})
      .defaults(std::string("diode"));
  bind_compartment(keys, "systemic_arteries", p.systemic_arterial, &P::systemic_arterial);
  bind_compartment(keys, "systemic_veins", p.systemic_venous, &P::systemic_venous);
  bind_compartment(keys, "pulmonary_arteries", p.pulmonary_arterial, &P::pulmonary_arterial);
  bind_compartment(keys, "pulmonary_veins", p.pulmonary_venous, &P::pulmonary_venous);
}

void check(const io::KeyBinder& keys, const CirculationKeys& k)
{
  const CirculationParameters& p = k.parameters;
  for (const ChamberParameters* c : {&p.left_atrium, &p.left_ventricle, &p.right_atrium, &p.right_ventricle})
    if (c->contraction_time + c->relaxation_time > 1.0)
      keys.fail(c->relaxation_time, "with " + keys.key_of(c->contraction_time) +
                                        " it exceeds one beat (their sum must be at most 1)");
  for (const DiodeValve* v : {&p.mitral, &p.aortic, &p.tricuspid, &p.pulmonary})
    if (!(v->closed_resistance > v->open_resistance))
      keys.fail(v->closed_resistance, "must be above " + keys.key_of(v->open_resistance));
}

} // namespace ibvalve::circulation
