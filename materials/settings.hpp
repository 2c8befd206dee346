#pragma once
// Named parameter presets and the case-file keys that choose a material.
//
// Presets hold the study's fitted parameters (Zhu et al. 2021, means of nine porcine samples) and a
// few classic ones, written in the user's units (kPa for moduli, as the papers give them) and
// converted to CGS (dyn/cm^2) when a law is built. A case file picks a material under a table, e.g.
//
//   [leaflet.material]
//   law = "W1"                 # or preset = "zhu2021-W1", or both (explicit keys override the preset)
//   C10 = 1.21                 # kPa
//   C01 = 7.99
//   k1 = 24.23                 # kPa
//   k2 = 57.62
//   fiber_compression = "off"  # fibers carry no load when shortened (I4 < 1)
//   penalty = "log"            # kappa/2 (ln J)^2
//   bulk_modulus = 1000.0      # kPa
// or a law written as a formula of the invariants (expression_law.hpp, docs/materials.md):
//   law = "expression"
//   energy = "c10*(I1bar - 3) + k1/(2*k2)*(exp(k2*(I4 - 1)^2) - 1)"
//   parameters = { c10 = 1.21, k1 = 24.23, k2 = 57.62 }
//   moduli = ["c10", "k1"]     # the parameters in kPa; the others are dimensionless
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "io/key_binder.hpp"
#include "materials/expression_law.hpp"
#include "materials/law.hpp"
#include "materials/material.hpp"

namespace ibvalve::materials {

/// The `law` value of a law written as a formula.
inline constexpr const char* expression_law_name = "expression";

struct Preset {
  std::string name;
  LawKind law;
  std::vector<double> values; ///< user units: kPa for moduli, dimensionless otherwise
  std::string source;
};

std::span<const Preset> presets();
const Preset* find_preset(std::string_view name);
/// Converts parameters in user units (kPa for moduli) to CGS, and back.
std::vector<double> to_cgs(LawKind law, std::span<const double> user_values);
std::vector<double> to_user_units(LawKind law, std::span<const double> cgs_values);

/// What a model recommends for one of its material tables: where the case skeleton (`ibvalve keys
/// --format toml`) starts from, a preset or a law with its parameters (in the case file's units, kPa for
/// moduli), and the isotropic invariant's default.
struct MaterialRecommendation {
  std::string preset = "zhu2021-W1";
  std::string law; ///< with `parameters`, when `preset` is empty
  std::vector<std::pair<std::string, double>> parameters;
  std::string isotropic_invariant = "I1";
};

/// A material table's keys as the case gives them (io/key_binder.hpp), before material_settings resolves
/// the law they describe. A key without a default that the case leaves out has no value (KeyBinder::has).
struct MaterialKeys {
  std::string law, preset, energy;
  /// One per name of every built-in law's parameters (the keys `C10`, `k1`, ...), CGS.
  std::vector<double> parameters;
  /// law expression: the formula's `parameters = { name = value, ... }`, as written.
  std::vector<std::pair<std::string, double>> formula_parameters;
  std::vector<std::string> moduli;
  LawOptions options;
  PenaltyKind penalty = PenaltyKind::log;
  double bulk_modulus = 0.0; ///< dyn/cm^2
};

/// Declares (a Schema binder) or reads (a Config binder) the keys of a material table under `prefix`
/// (e.g. "leaflet.material"); `recommended` is where the case skeleton starts from.
void bind(io::KeyBinder& keys, MaterialKeys& k, const std::string& prefix,
          const MaterialRecommendation& recommended = {});

/// The law = "expression" part of a material: the formula and its named parameters (CGS).
struct ExpressionDefinition {
  std::string energy;
  std::vector<ExpressionParameter> parameters;
};

/// Everything a material table resolves to.
struct MaterialSettings {
  LawKind law = LawKind::neo_hookean; ///< the built-in law, unless `expression` is set
  std::vector<double> parameters;     ///< CGS
  std::optional<ExpressionDefinition> expression;
  LawOptions options;
  PenaltyKind penalty = PenaltyKind::log;
  double bulk_modulus = 0.0; ///< dyn/cm^2
  std::string preset;        ///< empty when none was named
  /// Warnings about the law (an expression's loss of convexity), for the caller to log.
  std::vector<std::string> warnings;

  /// "W1 (C10 = 1.21 kPa, C01 = 7.99, ...), fibers tension only, log penalty, kappa = 1000 kPa".
  std::string describe() const;
  std::shared_ptr<const Material> build() const;
  /// The expression law (only when `expression` is set).
  ExpressionLaw expression_law() const;

 private:
  /// ", fibers in tension only, log penalty with bulk modulus 1000 kPa".
  std::string describe_options() const;
};

/// Everything a material table resolves to: the keys `keys` read into `k` (bind), the law resolved from
/// them. Errors (no law, a parameter of another law, a preset of another law, a missing parameter) name
/// the file, line and key.
MaterialSettings material_settings(const io::KeyBinder& keys, const MaterialKeys& k);

/// Checks that an expression law reads no more fiber families than the part has (0, 1 or 2): an energy
/// reading I4 where there are no fibers, or I6/I8 with one family, is an input error naming the
/// `energy` key of the table `k` and the character where the invariant is first read.
void check_fiber_families(const MaterialSettings& material, int families, const io::KeyBinder& keys,
                          const MaterialKeys& k);

} // namespace ibvalve::materials
