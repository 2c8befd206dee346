#include "materials/settings.hpp"

#include <algorithm>
#include <cctype>
#include <sstream>

#include "base/units.hpp"
#include "materials/expression_checks.hpp"

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

/// The built-in laws' parameters, one key each (C10, k1, ...): a preset supplies those the case leaves
/// out; the recommended law's are the skeleton's examples.
void bind_law_parameters(io::KeyBinder& keys, MaterialKeys& k, const std::string& p,
                         const MaterialRecommendation& recommended)
{
  const std::string preset_key = keys.full(p + "preset");
  const auto names = all_parameters();
  k.parameters.assign(names.size(), 0.0); // bound in place below: not resized after
  for (std::size_t i = 0; i < names.size(); ++i) {
    const auto& [name, info] = names[i];
    std::string used_by;
    for (const LawInfo& law : all_laws())
      for (const ParameterInfo& q : law.parameters)
        if (q.name == name) used_by += (used_by.empty() ? "" : ", ") + law.name;
    const std::string parameter = name;
    auto key =
        keys.real(p + name, info->doc + " (" + used_by + ")", k.parameters[i])
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
    for (const auto& [given, value] : recommended.parameters)
      if (given == name) key.example(value);
  }
}

/// How the law is applied: its fibers under compression, its reference state, its isotropic invariant and
/// its volumetric penalty.
void bind_options(io::KeyBinder& keys, MaterialKeys& k, const std::string& p,
                  const MaterialRecommendation& recommended)
{
  keys.choice(p + "fiber_compression",
              "\"off\": a fiber family carries no load when shortened (I4 < 1); \"on\": the law as written",
              k.options.fiber_compression,
              {{"off", FiberCompression::excluded}, {"on", FiberCompression::included}})
      .defaults(std::string("off"));
  keys.choice(p + "reference_state",
              "\"pressure-like\": adds -2 dW/dI1(I) ln J so that P(I) = 0; \"as-written\": the law alone",
              k.options.reference_state,
              {{"pressure-like", ReferenceState::pressure_like}, {"as-written", ReferenceState::as_written}})
      .defaults(std::string("pressure-like"));
  keys.choice(p + "isotropic_invariant",
              "\"I1\": the isotropic part reads tr C, as the law is written; \"isochoric\": it reads "
              "J^(-2/3) tr C (the same for incompressible tissue; resists the collapse of an element "
              "corner, docs/materials.md)",
              k.options.isotropic_invariant,
              {{"I1", IsotropicInvariant::I1}, {"isochoric", IsotropicInvariant::isochoric}})
      .defaults(recommended.isotropic_invariant);
  std::vector<std::pair<std::string, PenaltyKind>> penalties;
  for (const auto kind :
       {PenaltyKind::none, PenaltyKind::log, PenaltyKind::quadratic_log, PenaltyKind::quadratic})
    penalties.emplace_back(penalty_name(kind), kind);
  keys.choice(p + "penalty",
              "volumetric penalty: log = kappa/2 (ln J)^2, quadratic-log = kappa/4 (J^2-1-2 ln J), "
              "quadratic = kappa/2 (J-1)^2, none",
              k.penalty, penalties)
      .defaults(std::string("log"));
  keys.real(p + "bulk_modulus", "bulk modulus kappa of the volumetric penalty", k.bulk_modulus)
      .unit("kPa")
      .non_negative()
      .defaults(1000.0);
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

void bind(io::KeyBinder& keys, MaterialKeys& k, const std::string& prefix,
          const MaterialRecommendation& recommended)
{
  const std::string p = prefix.empty() ? "" : prefix + ".";
  std::vector<std::string> law_choices, preset_choices;
  for (const LawInfo& law : all_laws()) law_choices.push_back(law.name);
  law_choices.push_back(expression_law_name);
  for (const Preset& preset : presets()) preset_choices.push_back(preset.name);
  // Keys left out take the preset's values (config.toml writes them out, naming the preset).
  const std::string preset_key = keys.full(p + "preset");
  auto law = keys.string(p + "law",
                         "constitutive law (" + law_names() +
                             ", or expression: a formula in `energy`); implied by `preset` when omitted",
                         k.law)
                 .choices(law_choices)
                 .preset(preset_key, [](const std::string& name) -> std::optional<io::Value> {
                   const Preset* preset = find_preset(name);
                   if (!preset) return std::nullopt;
                   return law_info(preset->law).name;
                 });
  // A case needs a law or a preset: the skeleton of `ibvalve keys --format toml` starts from the
  // recommended one.
  auto preset = keys.string(p + "preset",
                            "named parameter set; explicit parameter keys override its values (with "
                            "law = \"expression\": its "
                            "law's formula and parameters, which `energy` and `parameters` override)",
                            k.preset)
                    .choices(preset_choices);
  if (!recommended.preset.empty()) preset.example(recommended.preset);
  if (!recommended.law.empty()) law.example(recommended.law);
  bind_law_parameters(keys, k, p, recommended);
  keys.string(p + "energy",
              "law expression: the strain energy as a formula of I1, I1bar, I2, I4, I6, I8, J and the "
              "parameters (docs/materials.md)",
              k.energy);
  keys.named_reals(p + "parameters", "law expression: the formula's parameters, { name = value, ... }",
                   k.formula_parameters);
  keys.strings(p + "moduli", "law expression: the parameters given in kPa (the others are dimensionless)",
               k.moduli);
  bind_options(keys, k, p, recommended);
}

namespace {

bool is_identifier(const std::string& name)
{
  if (name.empty() || !(std::isalpha(static_cast<unsigned char>(name[0])) || name[0] == '_')) return false;
  return std::all_of(name.begin(), name.end(),
                     [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

/// "character 17: " for a position in a formula (1-based, as an editor counts).
std::string at_character(std::size_t position)
{
  return position == std::string::npos ? "" : "character " + std::to_string(position + 1) + ": ";
}

/// The built-in law's parameters: from the preset, overridden by explicit keys.
void read_builtin_law(const io::KeyBinder& keys, const MaterialKeys& k, const Preset* preset,
                      MaterialSettings& s)
{
  const std::string only_expression =
      "only for law = \"expression\" (law " + law_info(s.law).name + " is built in)";
  if (keys.has(k.energy)) keys.fail(k.energy, only_expression);
  if (keys.has(k.formula_parameters)) keys.fail(k.formula_parameters, only_expression);
  if (keys.has(k.moduli)) keys.fail(k.moduli, only_expression);
  const LawInfo& info = law_info(s.law);
  if (preset) {
    s.preset = preset->name;
    s.parameters = to_cgs(s.law, preset->values);
  } else {
    s.parameters.assign(info.parameters.size(), -1.0);
  }
  // Explicit parameters: each must belong to the law; each of the law's must be known.
  const auto names = all_parameters();
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (!keys.has(k.parameters[i])) continue;
    const auto it = std::find_if(info.parameters.begin(), info.parameters.end(),
                                 [&](const ParameterInfo& q) { return q.name == names[i].first; });
    if (it == info.parameters.end()) {
      std::string own;
      for (const auto& q : info.parameters) own += (own.empty() ? "" : ", ") + q.name;
      keys.fail(k.parameters[i], "not a parameter of law " + info.name + " (its parameters: " + own + ")");
    }
    s.parameters[static_cast<std::size_t>(it - info.parameters.begin())] = k.parameters[i];
  }
  for (std::size_t i = 0; i < s.parameters.size(); ++i)
    if (s.parameters[i] < 0.0)
      keys.fail(k.law, "law " + info.name + " needs parameter " + info.parameters[i].name +
                           " (give it, or a preset)");
}

/// A preset's parameters as a formula's (CGS; the law's moduli are the preset's kPa values).
std::vector<ExpressionParameter> preset_parameters(const Preset& preset)
{
  std::vector<ExpressionParameter> out;
  const LawInfo& info = law_info(preset.law);
  for (std::size_t i = 0; i < info.parameters.size() && i < preset.values.size(); ++i) {
    const bool modulus = info.parameters[i].is_modulus;
    out.push_back(
        {info.parameters[i].name, modulus ? preset.values[i] * units::kPa : preset.values[i], modulus});
  }
  return out;
}

/// law = "expression": the formula and its parameters, the preset's law's where the keys leave them out:
/// `energy` and the `parameters` entries override them, and `moduli` defaults to the law's moduli.
ExpressionDefinition expression_definition(const io::KeyBinder& keys, const MaterialKeys& k,
                                           const Preset* preset, std::vector<std::string>& moduli)
{
  // A named number of `parameters`: its key, "...material.parameters.<name>", for messages about it.
  const auto fail_parameter = [&](const std::string& name, const std::string& message) {
    keys.config_of(k.formula_parameters).fail(keys.key_of(k.formula_parameters) + "." + name, message);
  };
  ExpressionDefinition definition;
  definition.energy = keys.has(k.energy) ? k.energy : law_info(preset->law).energy;
  if (keys.has(k.moduli)) {
    moduli = k.moduli;
  } else if (preset) {
    for (const ParameterInfo& q : law_info(preset->law).parameters)
      if (q.is_modulus) moduli.push_back(q.name);
  }
  if (preset) definition.parameters = preset_parameters(*preset);
  for (const auto& [name, value] : k.formula_parameters) {
    if (!is_identifier(name))
      fail_parameter(name, "a parameter's name is a letter or _ followed by letters, digits or _");
    if (std::find(expression_invariants.begin(), expression_invariants.end(), name) !=
        expression_invariants.end())
      fail_parameter(name, "'" + name + "' is an invariant, not a parameter");
    const bool modulus = std::find(moduli.begin(), moduli.end(), name) != moduli.end();
    const ExpressionParameter given{name, modulus ? value * units::kPa : value, modulus};
    const auto same = std::find_if(definition.parameters.begin(), definition.parameters.end(),
                                   [&](const ExpressionParameter& q) { return q.name == name; });
    if (same != definition.parameters.end())
      *same = given;
    else
      definition.parameters.push_back(given);
  }
  return definition;
}

/// law = "expression": the formula and its parameters, parsed and checked (expression_checks.hpp).
void read_expression_law(const io::KeyBinder& keys, const MaterialKeys& k, const Preset* preset,
                         MaterialSettings& s)
{
  for (const double& parameter : k.parameters)
    if (keys.has(parameter))
      keys.fail(parameter, "not a key of law expression (its parameters go in `parameters = { ... }`)");
  if (!keys.has(k.energy) && !preset)
    keys.fail(k.law, "law expression needs `energy`, a formula of the invariants, and its `parameters` (or a "
                     "preset, whose law's formula it takes)");
  std::vector<std::string> moduli;
  ExpressionDefinition definition = expression_definition(keys, k, preset, moduli);
  if (preset) s.preset = preset->name;
  std::string names;
  for (const ExpressionParameter& q : definition.parameters) names += (names.empty() ? "" : ", ") + q.name;
  for (const std::string& name : moduli)
    if (keys.has(k.moduli) && std::none_of(definition.parameters.begin(), definition.parameters.end(),
                                           [&](const ExpressionParameter& q) { return q.name == name; }))
      keys.fail(k.moduli, "'" + name + "' is not one of the parameters (" + names + ")");
  const auto fail_at = [&](std::size_t position, const std::string& message) {
    keys.fail(k.energy, at_character(position) + message);
  };
  try {
    const ExpressionLaw law(definition.energy, definition.parameters, s.options);
    for (std::size_t i = 0; i < definition.parameters.size(); ++i)
      if (!law.formula().uses(static_cast<int>(expression_invariants.size() + i))) {
        const std::string& name = definition.parameters[i].name;
        if (std::any_of(k.formula_parameters.begin(), k.formula_parameters.end(),
                        [&](const auto& given) { return given.first == name; }))
          keys.config_of(k.formula_parameters)
              .fail(keys.key_of(k.formula_parameters) + "." + name, "not used in the energy");
        keys.fail(k.energy,
                  "parameter " + name + " of preset \"" + preset->name + "\" is not used in the energy");
      }
    if (const auto problem = check_expression_law(law)) fail_at(problem->position, problem->message);
    const std::string energy_key = keys.key_of(k.energy);
    for (const std::string& warning : convexity_warnings(law))
      s.warnings.push_back(keys.config_of(k.energy).where(energy_key) + ": " + energy_key + ": " + warning);
  } catch (const FormulaError& e) {
    fail_at(e.position(), e.what());
  }
  s.expression = std::move(definition);
}

} // namespace

MaterialSettings material_settings(const io::KeyBinder& keys, const MaterialKeys& k)
{
  MaterialSettings s;
  s.options = k.options;
  s.penalty = k.penalty;
  s.bulk_modulus = k.bulk_modulus;

  const Preset* preset = keys.has(k.preset) ? find_preset(k.preset) : nullptr;
  if (keys.has(k.law) && k.law == expression_law_name) {
    read_expression_law(keys, k, preset, s);
    return s;
  }
  if (keys.has(k.law)) {
    s.law = *find_law(k.law);
    if (preset && preset->law != s.law)
      keys.fail(k.preset, "preset \"" + preset->name + "\" is for law " + law_info(preset->law).name +
                              ", not " + law_info(s.law).name);
  } else if (preset) {
    s.law = preset->law;
  } else {
    keys.fail(k.law, "give a law (" + law_names() + ", expression) or a preset");
  }
  read_builtin_law(keys, k, preset, s);
  return s;
}

void check_fiber_families(const MaterialSettings& material, int families, const io::KeyBinder& keys,
                          const MaterialKeys& k)
{
  if (!material.expression) return;
  const ExpressionLaw law = material.expression_law();
  if (law.fiber_families() <= families) return;
  // The invariants this part cannot give: I4 (symbol 3) without fibers; I6, I8 (4, 5) with one family.
  std::size_t first = std::string::npos;
  for (int symbol = families == 0 ? 3 : 4; symbol <= 5; ++symbol)
    first = std::min(first, law.formula().first_use(symbol));
  keys.fail(k.energy, at_character(first) + "the energy reads " +
                          (families == 0 ? "a fiber invariant, but this part has no fibers"
                                         : "a second fiber family (I6 or I8), but this part has one (I4)"));
}

std::string MaterialSettings::describe() const
{
  std::string text;
  if (expression) {
    text = "expression W = " + expression->energy + " (";
    for (std::size_t i = 0; i < expression->parameters.size(); ++i) {
      const auto& q = expression->parameters[i];
      text += (i ? ", " : "") + q.name + " = " + format(q.is_modulus ? q.value / units::kPa : q.value) +
              (q.is_modulus ? " kPa" : "");
    }
    return text + ")" + (preset.empty() ? "" : " from preset " + preset) + describe_options();
  }
  const LawInfo& info = law_info(law);
  const auto user = to_user_units(law, parameters);
  text = info.name + " (";
  for (std::size_t i = 0; i < user.size(); ++i)
    text += (i ? ", " : "") + info.parameters[i].name + " = " + format(user[i]) +
            (info.parameters[i].is_modulus ? " kPa" : "");
  text += ")";
  if (!preset.empty()) text += " from preset " + preset;
  return text + describe_options();
}

std::string MaterialSettings::describe_options() const
{
  std::string text = options.fiber_compression == FiberCompression::excluded
                         ? ", fibers in tension only"
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

ExpressionLaw MaterialSettings::expression_law() const
{
  if (!expression) throw std::logic_error("expression_law: the material's law is built in");
  return ExpressionLaw(expression->energy, expression->parameters, options);
}

std::shared_ptr<const Material> MaterialSettings::build() const
{
  std::shared_ptr<const StrainEnergy> law_ptr;
  if (expression)
    law_ptr = std::make_shared<ExpressionLaw>(expression_law());
  else
    law_ptr = std::make_shared<InvariantLaw>(law, parameters, options);
  return std::make_shared<Material>(std::move(law_ptr), VolumetricPenalty(penalty, bulk_modulus));
}

} // namespace ibvalve::materials
