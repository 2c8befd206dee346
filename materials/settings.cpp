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

io::Schema material_schema(const std::string& prefix, const MaterialRecommendation& recommended)
{
  io::Schema schema;
  const std::string p = prefix.empty() ? "" : prefix + ".";
  std::vector<std::string> law_choices, preset_choices;
  for (const LawInfo& law : all_laws()) law_choices.push_back(law.name);
  law_choices.push_back(expression_law_name);
  for (const Preset& preset : presets()) preset_choices.push_back(preset.name);
  // Keys left out take the preset's values (config.toml writes them out, naming the preset).
  const std::string preset_key = p + "preset";
  auto law = schema
                 .add_string(p + "law",
                             "constitutive law (" + law_names() +
                                 ", or expression: a formula in `energy`); implied by `preset` when omitted")
                 .choices(law_choices)
                 .preset(preset_key, [](const std::string& name) -> std::optional<io::Value> {
                   const Preset* preset = find_preset(name);
                   if (!preset) return std::nullopt;
                   return law_info(preset->law).name;
                 });
  // A case needs a law or a preset: the skeleton of `ibvalve keys --format toml` starts from the
  // recommended one.
  auto preset =
      schema
          .add_string(p + "preset", "named parameter set; explicit parameter keys override its values (with "
                                    "law = \"expression\": its "
                                    "law's formula and parameters, which `energy` and `parameters` override)")
          .choices(preset_choices);
  if (!recommended.preset.empty()) preset.example(recommended.preset);
  if (!recommended.law.empty()) law.example(recommended.law);
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
    for (const auto& [given, value] : recommended.parameters)
      if (given == name) key.example(value);
  }
  schema.add_string(p + "energy",
                    "law expression: the strain energy as a formula of I1, I1bar, I2, I4, I6, I8, J and the "
                    "parameters (docs/materials.md)");
  schema.add_real_table(p + "parameters", "law expression: the formula's parameters, { name = value, ... }");
  schema.add_string_list(p + "moduli",
                         "law expression: the parameters given in kPa (the others are dimensionless)");
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
      .defaults(recommended.isotropic_invariant);
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
void read_builtin_law(const io::Config& config, const std::string& p, const Preset* preset,
                      MaterialSettings& s)
{
  for (const char* key : {"energy", "parameters", "moduli"})
    if (config.has(p + key))
      config.fail(p + key, "only for law = \"expression\" (law " + law_info(s.law).name + " is built in)");
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

/// law = "expression": the formula and its parameters, parsed and checked (expression_checks.hpp).
/// With a preset, its law's formula and parameters are the defaults (`energy` and `parameters`
/// entries override them) and `moduli` defaults to the law's moduli.
void read_expression_law(const io::Config& config, const std::string& p, const Preset* preset,
                         MaterialSettings& s)
{
  for (const auto& [name, spec] : all_parameters())
    if (config.has(p + name))
      config.fail(p + name, "not a key of law expression (its parameters go in `parameters = { ... }`)");
  if (!config.has(p + "energy") && !preset)
    config.fail(p + "law",
                "law expression needs `energy`, a formula of the invariants, and its `parameters` (or a "
                "preset, whose law's formula it takes)");
  ExpressionDefinition definition;
  definition.energy = config.has(p + "energy") ? config.string(p + "energy") : law_info(preset->law).energy;
  std::vector<std::string> moduli;
  if (config.has(p + "moduli")) {
    moduli = config.strings(p + "moduli");
  } else if (preset) {
    for (const ParameterInfo& q : law_info(preset->law).parameters)
      if (q.is_modulus) moduli.push_back(q.name);
  }
  if (preset) {
    s.preset = preset->name;
    definition.parameters = preset_parameters(*preset);
  }
  const auto given_parameters = config.named_reals(p + "parameters");
  for (const auto& [name, value] : given_parameters) {
    const std::string key = p + "parameters." + name;
    if (!is_identifier(name))
      config.fail(key, "a parameter's name is a letter or _ followed by letters, digits or _");
    if (std::find(expression_invariants.begin(), expression_invariants.end(), name) !=
        expression_invariants.end())
      config.fail(key, "'" + name + "' is an invariant, not a parameter");
    const bool modulus = std::find(moduli.begin(), moduli.end(), name) != moduli.end();
    const ExpressionParameter given{name, modulus ? value * units::kPa : value, modulus};
    const auto same = std::find_if(definition.parameters.begin(), definition.parameters.end(),
                                   [&](const ExpressionParameter& q) { return q.name == name; });
    if (same != definition.parameters.end())
      *same = given;
    else
      definition.parameters.push_back(given);
  }
  std::string names;
  for (const ExpressionParameter& q : definition.parameters) names += (names.empty() ? "" : ", ") + q.name;
  for (const std::string& name : moduli)
    if (config.has(p + "moduli") &&
        std::none_of(definition.parameters.begin(), definition.parameters.end(),
                     [&](const ExpressionParameter& q) { return q.name == name; }))
      config.fail(p + "moduli", "'" + name + "' is not one of the parameters (" + names + ")");
  const auto fail_at = [&](std::size_t position, const std::string& message) {
    config.fail(p + "energy", at_character(position) + message);
  };
  try {
    const ExpressionLaw law(definition.energy, definition.parameters, s.options);
    for (std::size_t i = 0; i < definition.parameters.size(); ++i)
      if (!law.formula().uses(static_cast<int>(expression_invariants.size() + i))) {
        const std::string& name = definition.parameters[i].name;
        if (std::any_of(given_parameters.begin(), given_parameters.end(),
                        [&](const auto& given) { return given.first == name; }))
          config.fail(p + "parameters." + name, "not used in the energy");
        config.fail(p + "energy",
                    "parameter " + name + " of preset \"" + preset->name + "\" is not used in the energy");
      }
    if (const auto problem = check_expression_law(law)) fail_at(problem->position, problem->message);
    for (const std::string& warning : convexity_warnings(law))
      s.warnings.push_back(config.where(p + "energy") + ": " + p + "energy: " + warning);
  } catch (const FormulaError& e) {
    fail_at(e.position(), e.what());
  }
  s.expression = std::move(definition);
}

} // namespace

MaterialSettings read_material(const io::Config& config, const std::string& prefix)
{
  const std::string p = prefix.empty() ? "" : prefix + ".";
  MaterialSettings s;
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

  const Preset* preset = config.has(p + "preset") ? find_preset(config.string(p + "preset")) : nullptr;
  if (config.has(p + "law") && config.string(p + "law") == expression_law_name) {
    read_expression_law(config, p, preset, s);
    return s;
  }
  if (config.has(p + "law")) {
    s.law = *find_law(config.string(p + "law"));
    if (preset && preset->law != s.law)
      config.fail(p + "preset", "preset \"" + preset->name + "\" is for law " + law_info(preset->law).name +
                                    ", not " + law_info(s.law).name);
  } else if (preset) {
    s.law = preset->law;
  } else {
    config.fail(p + "law", "give a law (" + law_names() + ", expression) or a preset");
  }
  read_builtin_law(config, p, preset, s);
  return s;
}

void check_fiber_families(const MaterialSettings& material, int families, const io::Config& config,
                          const std::string& prefix)
{
  if (!material.expression) return;
  const ExpressionLaw law = material.expression_law();
  if (law.fiber_families() <= families) return;
  // The invariants this part cannot give: I4 (symbol 3) without fibers; I6, I8 (4, 5) with one family.
  std::size_t first = std::string::npos;
  for (int symbol = families == 0 ? 3 : 4; symbol <= 5; ++symbol)
    first = std::min(first, law.formula().first_use(symbol));
  const std::string p = prefix.empty() ? "" : prefix + ".";
  config.fail(p + "energy",
              at_character(first) + "the energy reads " +
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
