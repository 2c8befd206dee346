#include "materials/settings.hpp"

#include <algorithm>
#include <sstream>

#include "base/units.hpp"

namespace ibvalve::materials {

namespace {

const std::vector<Preset>& preset_table()
{
  static const std::vector<Preset> table{
      {"zhu2021-W1",
       LawKind::W1,
       {1.21, 7.99, 24.23, 57.62},
       "Zhu et al. 2021, Front. Physiol. 12:682893: mean of nine porcine leaflets"},
      {"zhu2021-W2",
       LawKind::W2,
       {1.18, 55.04, 8.08, 54.00},
       "Zhu et al. 2021, Front. Physiol. 12:682893: mean of nine porcine leaflets"},
      {"zhu2021-W3",
       LawKind::W3,
       {19.59, 12.94, 77.79},
       "Zhu et al. 2021, Front. Physiol. 12:682893: mean of nine porcine leaflets"},
      {"holzapfel2000-media",
       LawKind::hgo,
       {3.0, 2.3632, 0.8393, 0.0},
       "Holzapfel, Gasser & Ogden 2000, J. Elasticity 61:1, media (fibers at +-29 deg)"},
      {"holzapfel2000-adventitia",
       LawKind::hgo,
       {0.3, 0.562, 0.7112, 0.0},
       "Holzapfel, Gasser & Ogden 2000, J. Elasticity 61:1, adventitia (fibers at +-49.98 deg)"},
  };
  return table;
}

/// Every parameter name of every law, with its unit (the same name has the same meaning/unit in
/// every law that uses it: mu, k1 moduli; k2 exponent).
std::vector<std::pair<std::string, const ParameterInfo*>> all_parameters()
{
  std::vector<std::pair<std::string, const ParameterInfo*>> out;
  for (const LawInfo& law : all_laws())
    for (const ParameterInfo& p : law.parameters)
      if (std::none_of(out.begin(), out.end(), [&](const auto& e) { return e.first == p.name; }))
        out.emplace_back(p.name, &p);
  return out;
}

std::string format(double x)
{
  std::ostringstream os;
  os.precision(6);
  os << x;
  return os.str();
}

} // namespace

std::span<const Preset> presets()
{
  return preset_table();
}

const Preset* find_preset(std::string_view name)
{
  for (const Preset& p : preset_table())
    if (p.name == name) return &p;
  return nullptr;
}

std::vector<double> to_cgs(LawKind law, std::span<const double> user_values)
{
  const LawInfo& info = law_info(law);
  std::vector<double> out(user_values.begin(), user_values.end());
  for (std::size_t i = 0; i < out.size() && i < info.parameters.size(); ++i)
    if (info.parameters[i].is_modulus) out[i] *= units::kPa;
  return out;
}

std::vector<double> to_user_units(LawKind law, std::span<const double> cgs_values)
{
  const LawInfo& info = law_info(law);
  std::vector<double> out(cgs_values.begin(), cgs_values.end());
  for (std::size_t i = 0; i < out.size() && i < info.parameters.size(); ++i)
    if (info.parameters[i].is_modulus) out[i] /= units::kPa;
  return out;
}

io::Schema material_schema(const std::string& prefix)
{
  io::Schema schema;
  const std::string p = prefix.empty() ? "" : prefix + ".";
  std::vector<std::string> law_choices, preset_choices;
  for (const LawInfo& law : all_laws()) law_choices.push_back(law.name);
  for (const Preset& preset : presets()) preset_choices.push_back(preset.name);
  // Keys left out take the preset's values (config.toml writes them out, naming the preset).
  const std::string preset_key = p + "preset";
  schema.add_string(p + "law", "constitutive law (" + law_names() + "); implied by `preset` when omitted")
      .choices(law_choices)
      .preset(preset_key, [](const std::string& name) -> std::optional<io::Value> {
        const Preset* preset = find_preset(name);
        if (!preset) return std::nullopt;
        return law_info(preset->law).name;
      });
  // A case needs a law or a preset: the skeleton of `ibvalve keys --format toml` starts from a preset.
  schema.add_string(p + "preset", "named parameter set; explicit parameter keys override its values")
      .choices(preset_choices)
      .example(std::string("zhu2021-W1"));
  for (const auto& [name, info] : all_parameters()) {
    std::string used_by;
    for (const LawInfo& law : all_laws())
      for (const ParameterInfo& q : law.parameters)
        if (q.name == name) used_by += (used_by.empty() ? "" : ", ") + law.name;
    const std::string parameter = name;
    auto key =
        schema.add_real(p + name, info->doc + " (" + used_by + ")")
            .non_negative()
            .preset(preset_key, [parameter](const std::string& preset_name) -> std::optional<io::Value> {
              const Preset* preset = find_preset(preset_name);
              if (!preset) return std::nullopt;
              const auto& parameters = law_info(preset->law).parameters;
              for (std::size_t i = 0; i < parameters.size() && i < preset->values.size(); ++i)
                if (parameters[i].name == parameter) // the run's value, in CGS
                  return preset->values[i] * (parameters[i].is_modulus ? units::kPa : 1.0);
              return std::nullopt;
            });
    if (info->is_modulus) key.unit("kPa");
    if (info->upper < 1e300) key.at_most(info->upper);
  }
  schema
      .add_string(
          p + "fiber_compression",
          "\"off\": a fiber family carries no load when shortened (I4 < 1); \"on\": the law as written")
      .choices({"off", "on"})
      .defaults(std::string("off"));
  schema
      .add_string(p + "reference_state",
                  "\"pressure-like\": adds -2 dW/dI1(I) ln J so that P(I) = 0; \"as-written\": the law alone")
      .choices({"pressure-like", "as-written"})
      .defaults(std::string("pressure-like"));
  schema
      .add_string(p + "isotropic_invariant",
                  "\"I1\": the isotropic part reads tr C, as the law is written; \"isochoric\": it reads "
                  "J^(-2/3) tr C (the same for incompressible tissue; resists the collapse of an element "
                  "corner, docs/materials.md)")
      .choices({"I1", "isochoric"})
      .defaults(std::string("I1"));
  std::vector<std::string> penalty_choices;
  for (const auto kind :
       {PenaltyKind::none, PenaltyKind::log, PenaltyKind::quadratic_log, PenaltyKind::quadratic})
    penalty_choices.push_back(penalty_name(kind));
  schema
      .add_string(p + "penalty",
                  "volumetric penalty: log = kappa/2 (ln J)^2, quadratic-log = kappa/4 (J^2-1-2 ln J), "
                  "quadratic = kappa/2 (J-1)^2, none")
      .choices(penalty_choices)
      .defaults(std::string("log"));
  schema.add_real(p + "bulk_modulus", "bulk modulus kappa of the volumetric penalty")
      .unit("kPa")
      .non_negative()
      .defaults(1000.0);
  return schema;
}

MaterialSettings read_material(const io::Config& config, const std::string& prefix)
{
  const std::string p = prefix.empty() ? "" : prefix + ".";
  MaterialSettings s;
  const Preset* preset = config.has(p + "preset") ? find_preset(config.string(p + "preset")) : nullptr;
  if (config.has(p + "law")) {
    s.law = *find_law(config.string(p + "law"));
    if (preset && preset->law != s.law)
      config.fail(p + "preset", "preset \"" + preset->name + "\" is for law " + law_info(preset->law).name +
                                    ", not " + law_info(s.law).name);
  } else if (preset) {
    s.law = preset->law;
  } else {
    config.fail(p + "law", "give a law (" + law_names() + ") or a preset");
  }
  const LawInfo& info = law_info(s.law);
  if (preset) {
    s.preset = preset->name;
    s.parameters = to_cgs(s.law, preset->values);
  } else {
    s.parameters.assign(info.parameters.size(), -1.0);
  }
  // Explicit parameters: each must belong to the law; each of the law's must be known.
  for (const auto& [name, spec] : all_parameters()) {
    const std::string key = p + name;
    if (!config.has(key)) continue;
    const auto it = std::find_if(info.parameters.begin(), info.parameters.end(),
                                 [&](const ParameterInfo& q) { return q.name == name; });
    if (it == info.parameters.end()) {
      std::string own;
      for (const auto& q : info.parameters) own += (own.empty() ? "" : ", ") + q.name;
      config.fail(key, "not a parameter of law " + info.name + " (its parameters: " + own + ")");
    }
    s.parameters[static_cast<std::size_t>(it - info.parameters.begin())] = config.real(key);
  }
  for (std::size_t i = 0; i < s.parameters.size(); ++i)
    if (s.parameters[i] < 0.0)
      config.fail(p + "law", "law " + info.name + " needs parameter " + info.parameters[i].name +
                                 " (give it, or a preset)");
  s.options.fiber_compression = config.string(p + "fiber_compression") == "on" ? FiberCompression::included
                                                                               : FiberCompression::excluded;
  s.options.reference_state = config.string(p + "reference_state") == "as-written"
                                  ? ReferenceState::as_written
                                  : ReferenceState::pressure_like;
  s.options.isotropic_invariant = config.string(p + "isotropic_invariant") == "isochoric"
                                      ? IsotropicInvariant::isochoric
                                      : IsotropicInvariant::I1;
  s.penalty = *find_penalty(config.string(p + "penalty"));
  s.bulk_modulus = config.real(p + "bulk_modulus");
  return s;
}

std::string MaterialSettings::describe() const
{
  const LawInfo& info = law_info(law);
  const auto user = to_user_units(law, parameters);
  std::string text = info.name + " (";
  for (std::size_t i = 0; i < user.size(); ++i)
    text += (i ? ", " : "") + info.parameters[i].name + " = " + format(user[i]) +
            (info.parameters[i].is_modulus ? " kPa" : "");
  text += ")";
  if (!preset.empty()) text += " from preset " + preset;
  text += options.fiber_compression == FiberCompression::excluded ? ", fibers in tension only"
                                                                  : ", fibers in tension and compression";
  if (options.isotropic_invariant == IsotropicInvariant::isochoric)
    text += ", isotropic part in J^(-2/3) I1";
  else if (options.reference_state == ReferenceState::as_written)
    text += ", reference term off";
  if (penalty == PenaltyKind::none)
    text += ", no volumetric penalty";
  else
    text += ", " + penalty_name(penalty) + " penalty with bulk modulus " + format(bulk_modulus / units::kPa) +
            " kPa";
  return text;
}

std::shared_ptr<const Material> MaterialSettings::build() const
{
  auto law_ptr = std::make_shared<InvariantLaw>(law, parameters, options);
  return std::make_shared<Material>(std::move(law_ptr), VolumetricPenalty(penalty, bulk_modulus));
}

} // namespace ibvalve::materials
