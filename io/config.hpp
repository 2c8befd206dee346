#pragma once
// Case files: TOML read with toml++, checked against a schema of keys with types, units and ranges.
//
// A Schema lists every key a case file may hold (dotted paths such as "fluid.viscosity"), with its
// kind, the unit the user writes it in, its default and its allowed range or choices. Config::validate
// checks a parsed file against it: an unknown key, a wrong type, an out-of-range value, a missing
// required key or a missing file each throw one InputError line "file:line: key: what is wrong".
// A valid Config holds every key, defaults filled in, and hands out values converted to CGS.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include <toml++/toml.h>

namespace ibvalve::io {

enum class ValueKind {
  boolean,
  integer,
  real,
  string,
  real_list,
  integer_list,
  string_list,
  table_list,
  real_table
};

using Value = std::variant<bool, std::int64_t, double, std::string, std::vector<double>,
                           std::vector<std::int64_t>, std::vector<std::string>>;

class Schema;

struct KeySpec {
  std::string key;
  ValueKind kind = ValueKind::real;
  std::string doc;
  std::string unit; // as written in the case file; read back in CGS
  bool required = false;
  std::optional<Value> default_value;
  std::optional<Value> example; // a required key's value to start from (Schema::toml_skeleton)
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_inclusive = true;
  bool max_inclusive = true;
  std::vector<std::string> choices;
  std::size_t min_size = 0; // lists: fewest elements
  std::size_t max_size = std::numeric_limits<std::size_t>::max();
  bool is_path = false;                  // a string naming a file, relative to the case file's folder
  bool must_exist = false;               // ... which must exist when read
  std::shared_ptr<const Schema> element; // table_list: the schema of each element
  // Numbers (and list elements) outside [typical_min, typical_max] are valid but warned about: a
  // value written in another unit system (Pa s as cP, Pa as mmHg, mm as cm) lands far outside.
  double typical_min = -std::numeric_limits<double>::infinity();
  double typical_max = std::numeric_limits<double>::infinity();
  std::string typical_why;
  // A key a named preset supplies when it is not given: the key naming the preset (same table) and
  // the value the preset gives, as the case file would write it (nothing when it gives none).
  std::string preset_key;
  std::function<std::optional<Value>(const std::string& preset)> from_preset;
  // A key (same table) that makes this one unused when it is given: a generator's setting beside the
  // file given instead. The key is then left out of the case (no default, a given value set aside with
  // a warning), so what a run records holds no setting it did not use.
  std::string unused_with;
};

/// Sets the properties of one key; returned by the Schema::add_* calls.
class KeyBuilder {
 public:
  explicit KeyBuilder(KeySpec& spec) : spec_(&spec) {}
  KeyBuilder& unit(std::string unit);
  KeyBuilder& required();
  KeyBuilder& defaults(Value value);
  /// A value to start from for a required key (written into `ibvalve keys --format toml`).
  KeyBuilder& example(Value value);
  KeyBuilder& at_least(double min);
  KeyBuilder& above(double min);
  KeyBuilder& at_most(double max);
  KeyBuilder& below(double max);
  KeyBuilder& positive() { return above(0.0); }
  KeyBuilder& non_negative() { return at_least(0.0); }
  KeyBuilder& choices(std::vector<std::string> allowed);
  KeyBuilder& size(std::size_t n) { return sizes(n, n); }
  KeyBuilder& sizes(std::size_t min, std::size_t max);
  /// A path relative to the case file's folder; `must_exist` makes a missing file an input error.
  KeyBuilder& file(bool must_exist = true);
  /// Values outside [lo, hi] (in the key's unit) get a warning naming the range and `why`.
  KeyBuilder& typical(double lo, double hi, std::string why);
  /// When the key is not given, the preset named by `preset_key` supplies `value(preset name)`.
  KeyBuilder& preset(std::string preset_key, std::function<std::optional<Value>(const std::string&)> value);
  /// Not used when `key` is given (KeySpec::unused_with); the meaning says so.
  KeyBuilder& unused_with(std::string key);

 private:
  KeySpec* spec_;
};

class Schema {
 public:
  KeyBuilder add_boolean(std::string key, std::string doc);
  KeyBuilder add_integer(std::string key, std::string doc);
  KeyBuilder add_real(std::string key, std::string doc);
  KeyBuilder add_string(std::string key, std::string doc);
  KeyBuilder add_real_list(std::string key, std::string doc);
  KeyBuilder add_integer_list(std::string key, std::string doc);
  KeyBuilder add_string_list(std::string key, std::string doc);
  /// A table of numbers under names the user chooses (`key = { a = 1.0, b = 2.5 }`), for named
  /// parameters; the range applies to each number. Read with Config::named_reals.
  KeyBuilder add_real_table(std::string key, std::string doc);
  /// An array of tables ([[key]] in TOML), each element checked against `element`.
  KeyBuilder add_table_list(std::string key, Schema element, std::string doc);

  /// A key no longer read (a spelling of an older version): a case that gives it is refused with
  /// "file:line: key: <why>", where `why` names the key to write instead. Not listed with the keys.
  void retire(std::string key, std::string why);
  /// Why `key` is retired, or nullptr for a key never retired.
  const std::string* retired(std::string_view key) const;

  /// Adds every key (and retired key) of `other`; a key defined twice is a programming error.
  void merge(const Schema& other);
  const KeySpec* find(std::string_view key) const;
  /// True when some key starts with "prefix.".
  bool has_table(std::string_view prefix) const;
  /// Keys in the order they were added.
  std::span<const std::unique_ptr<KeySpec>> keys() const { return keys_; }
  /// A Markdown table of every key (for docs and `ibvalve run --help-config`).
  std::string markdown() const;
  /// A commented TOML case file with every key at its default (required keys at their example,
  /// optional keys without a default and table lists commented out), preceded by `head`; the keys in
  /// `fixed` at the value given there.
  std::string toml_skeleton(std::string_view head,
                            std::span<const std::pair<std::string, Value>> fixed = {}) const;

  Schema() = default;
  Schema(const Schema& other) { merge(other); }
  Schema& operator=(const Schema& other);
  Schema(Schema&&) = default;
  Schema& operator=(Schema&&) = default;

 private:
  KeyBuilder add(std::string key, ValueKind kind, std::string doc);
  std::vector<std::unique_ptr<KeySpec>> keys_;
  std::vector<std::pair<std::string, std::string>> retired_; // key, why
};

/// The Levenshtein distance of a and b (insertions, deletions, substitutions): how "did you mean"
/// suggestions for misspelt keys, tables and model names are chosen.
std::size_t edit_distance(std::string_view a, std::string_view b);

/// Parses a TOML file; a syntax error or a missing file throws InputError naming file and line.
toml::table parse_toml_file(const std::filesystem::path& file);
/// "file:line" where `node` was read (its own source's name, else `file`), or `file` alone for a node
/// without a line or none: how a message about a key of a TOML file starts.
std::string node_location(const toml::node* node, const std::filesystem::path& file);
/// Every value of a TOML table as (dotted key, value as TOML writes it), in the table's order; an
/// array of tables gives key[i].field.
std::vector<std::pair<std::string, std::string>> flattened(const toml::table& table);
/// Finds a key's spec by its dotted name (nullptr when unknown); lets overrides read bare words.
using KeyLookup = std::function<const KeySpec*(std::string_view key)>;
/// Applies "key=value" overrides given on the command line. The value is TOML, except that for a
/// string key (by `lookup`) a bare word is the string itself (--set fibers.rule=FD2), and for a
/// string list a bare word may be an element ([tube_outer, tube_inlet]). A value that is no TOML is
/// kept as a string, so that validation names the key and the type it expects.
void apply_overrides(toml::table& table, std::span<const std::string> overrides,
                     const KeyLookup& lookup = {});
/// The shortest text that reads back as exactly `x` (std::to_chars), with ".0" on a whole number so
/// that TOML reads it back as a float.
std::string format_real(double x);

/// A validated case file (or one element of a table list within it).
class Config {
 public:
  /// Checks `table` (read from `file`) against `schema` and fills in defaults.
  static Config validate(toml::table table, const std::filesystem::path& file, const Schema& schema);
  /// parse_toml_file + apply_overrides + validate.
  static Config load(const std::filesystem::path& file, const Schema& schema,
                     std::span<const std::string> overrides = {});

  bool has(std::string_view key) const;
  bool boolean(std::string_view key) const;
  std::int64_t integer(std::string_view key) const;
  /// In CGS: the value as written, times the unit's factor.
  double real(std::string_view key) const;
  std::string string(std::string_view key) const;
  /// A path key, resolved against the case file's folder.
  std::filesystem::path path(std::string_view key) const;
  /// A list of path keys, each resolved against the case file's folder.
  std::vector<std::filesystem::path> paths(std::string_view key) const;
  std::vector<double> reals(std::string_view key) const;
  std::vector<std::int64_t> integers(std::string_view key) const;
  std::vector<std::string> strings(std::string_view key) const;
  std::vector<Config> tables(std::string_view key) const;
  /// A real_table key's (name, value) pairs, in name order, as written (no unit conversion: the unit
  /// of each depends on what the names mean).
  std::vector<std::pair<std::string, double>> named_reals(std::string_view key) const;

  /// "case.toml:12" for a key (the file alone for a default).
  std::string where(std::string_view key) const;
  /// Throws the InputError "file:line: key: message", for checks a schema cannot express.
  [[noreturn]] void fail(std::string_view key, std::string_view message) const;

  const std::filesystem::path& file() const { return state_->file; }
  /// Values outside their key's typical range, one line each ("file:line: key: ..."), for the caller
  /// to print as warnings.
  const std::vector<std::string>& warnings() const { return state_->warnings; }
  /// The whole resolved configuration as TOML, every default written out, units in comments; a key a
  /// preset supplies is written with the preset's value (the file still validates as a case file).
  /// File paths are written absolute, or relative to `written_in` when given (the folder the text is
  /// written into: a run folder's config.toml then holds no path of the machine it ran on).
  std::string resolved_toml(const std::filesystem::path& written_in = {}) const;

 private:
  struct State {
    toml::table root;
    std::filesystem::path file;
    Schema schema;
    std::vector<std::string> warnings;
  };
  Config(std::shared_ptr<const State> state, const toml::table* table, const Schema* schema,
         std::string prefix)
      : state_(std::move(state)), table_(table), schema_(schema), prefix_(std::move(prefix))
  {
  }
  const toml::node* node(std::string_view key) const;
  const KeySpec& spec(std::string_view key) const;

  std::shared_ptr<const State> state_;
  const toml::table* table_;
  const Schema* schema_;
  std::string prefix_; // "fluid.boundary[2]" for an element of a table list
};

} // namespace ibvalve::io
