#include "io/config.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <functional>
#include <sstream>
#include <stdexcept>

#include "base/errors.hpp"
#include "base/units.hpp"
#include "io/files.hpp"
#include "io/schema_text.hpp"

namespace ibvalve::io {

using namespace detail; // the text helpers the schema, validation and writing share

// ---------------------------------------------------------------------------------------------
// Parsing and validation

std::size_t edit_distance(std::string_view a, std::string_view b)
{
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

namespace {

std::string source_name(const toml::source_region& region, const std::filesystem::path& fallback)
{
  if (region.path && !region.path->empty()) return *region.path;
  return fallback.string();
}

} // namespace

std::string node_location(const toml::node* node, const std::filesystem::path& file)
{
  if (node && node->source().begin.line > 0)
    return fmt::format("{}:{}", source_name(node->source(), file), node->source().begin.line);
  return file.string();
}

namespace {

[[noreturn]] void input_error(const toml::node* node, const std::filesystem::path& file, std::string_view key,
                              std::string_view message)
{
  throw InputError(node_location(node, file) + ": " + std::string(key) + ": " + std::string(message));
}

std::string suggestion(const Schema& schema, std::string_view key)
{
  std::string best;
  std::size_t best_distance = 4;
  for (const auto& spec : schema.keys()) {
    const std::size_t d = edit_distance(spec->key, key);
    if (d < best_distance) {
      best_distance = d;
      best = spec->key;
    }
  }
  return best.empty() ? "" : " (did you mean '" + best + "'?)";
}

std::string display_value(const toml::node& node)
{
  std::ostringstream os;
  if (const auto* x = node.as_floating_point())
    os << format_number(x->get()); // as written (0.004), not toml++'s 17 digits
  else
    node.visit([&](const auto& v) { os << v; });
  std::string text = os.str();
  if (text.size() > 40) text = text.substr(0, 37) + "...";
  return text;
}

/// The names of the tables at the level of `prefix` ("fluid", "time", ... for the root).
std::vector<std::string> table_names(const Schema& schema, std::string_view prefix)
{
  std::vector<std::string> names;
  const std::string start = prefix.empty() ? "" : std::string(prefix) + ".";
  for (const auto& spec : schema.keys()) {
    if (!spec->key.starts_with(start)) continue;
    const std::string rest = spec->key.substr(start.size());
    const auto dot = rest.find('.');
    const std::string name = dot == std::string::npos ? rest : rest.substr(0, dot);
    const bool is_table = dot != std::string::npos || spec->kind == ValueKind::table_list;
    if (is_table && std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  }
  return names;
}

std::string table_suggestion(const Schema& schema, std::string_view prefix, std::string_view name,
                             std::string_view display_prefix)
{
  std::string best;
  std::size_t best_distance = 3;
  for (const std::string& table : table_names(schema, prefix)) {
    const std::size_t d = edit_distance(table, name);
    if (d < best_distance) {
      best_distance = d;
      best = table;
    }
  }
  return best.empty() ? "" : " (did you mean '" + join_key(display_prefix, best) + "'?)";
}

struct Validator {
  const std::filesystem::path& file;
  std::vector<std::string>& warnings;

  void check_number(const toml::node& node, const KeySpec& spec, std::string_view display_key, double x) const
  {
    if (!std::isfinite(x)) input_error(&node, file, display_key, "must be a finite number");
    const bool low = spec.min_inclusive ? x < spec.min : x <= spec.min;
    const bool high = spec.max_inclusive ? x > spec.max : x >= spec.max;
    if (low || high)
      input_error(&node, file, display_key,
                  display_value(node) + " is out of range (must be " + range_text(spec) + ")");
    if (x < spec.typical_min || x > spec.typical_max) {
      const std::string unit = spec.unit.empty() ? "" : " " + spec.unit;
      warnings.push_back(node_location(&node, file) + ": " + std::string(display_key) + ": " +
                         display_value(node) + unit + " is outside the typical " + typical_text(spec) +
                         (spec.typical_why.empty() ? "" : " (" + spec.typical_why + ")"));
    }
  }

  double number(const toml::node& node, std::string_view display_key, bool integer) const
  {
    if (integer && !node.is_integer())
      input_error(&node, file, display_key, "expected an integer, got " + display_value(node));
    if (!node.is_number())
      input_error(&node, file, display_key, "expected a number, got " + display_value(node));
    return node.is_integer() ? static_cast<double>(*node.value<std::int64_t>()) : *node.value<double>();
  }

  void check_string(const toml::node& node, const KeySpec& spec, std::string_view display_key) const
  {
    if (!node.is_string())
      input_error(&node, file, display_key, "expected a string, got " + display_value(node));
    const std::string value = *node.value<std::string>();
    if (!spec.choices.empty() &&
        std::find(spec.choices.begin(), spec.choices.end(), value) == spec.choices.end())
      input_error(&node, file, display_key,
                  "\"" + value + "\" is not one of the allowed values: " + join(spec.choices, ", "));
    if (spec.is_path && spec.must_exist) {
      std::filesystem::path path(value);
      if (path.is_relative()) path = file.parent_path() / path;
      if (!std::filesystem::is_regular_file(path))
        input_error(&node, file, display_key, "no such file '" + path.string() + "'");
    }
  }

  void check_value(const toml::node& node, const KeySpec& spec, std::string_view display_key) const
  {
    switch (spec.kind) {
    case ValueKind::boolean:
      if (!node.is_boolean())
        input_error(&node, file, display_key, "expected true or false, got " + display_value(node));
      return;
    case ValueKind::integer:
    case ValueKind::real:
      check_number(node, spec, display_key, number(node, display_key, spec.kind == ValueKind::integer));
      return;
    case ValueKind::string:
      check_string(node, spec, display_key);
      return;
    case ValueKind::real_list:
    case ValueKind::integer_list:
    case ValueKind::string_list: {
      const auto* array = node.as_array();
      if (!array)
        input_error(&node, file, display_key,
                    "expected " + kind_name(spec.kind) + ", got " + display_value(node));
      if (array->size() < spec.min_size || array->size() > spec.max_size) {
        const std::string count = spec.min_size == spec.max_size
                                      ? fmt::to_string(spec.min_size)
                                      : fmt::format("{} to {}", spec.min_size, spec.max_size);
        input_error(&node, file, display_key,
                    fmt::format("expected {} values, got {}", count, array->size()));
      }
      for (std::size_t i = 0; i < array->size(); ++i) {
        const toml::node& item = *array->get(i);
        const std::string item_key = fmt::format("{}[{}]", display_key, i);
        if (spec.kind == ValueKind::string_list)
          check_string(item, spec, item_key);
        else
          check_number(item, spec, item_key, number(item, item_key, spec.kind == ValueKind::integer_list));
      }
      return;
    }
    case ValueKind::table_list: {
      const auto* array = node.as_array();
      if (!array || !array->is_array_of_tables())
        input_error(&node, file, display_key, "expected a list of tables ([[" + spec.key + "]] sections)");
      if (array->size() < spec.min_size || array->size() > spec.max_size)
        input_error(&node, file, display_key, fmt::format("expected at least {} entries", spec.min_size));
      return; // elements are validated by validate_table
    }
    case ValueKind::real_table: {
      const auto* table = node.as_table();
      if (!table)
        input_error(&node, file, display_key,
                    "expected " + kind_name(spec.kind) + ", got " + display_value(node));
      for (auto&& [name, item] : *table) {
        const std::string item_key = join_key(display_key, name.str());
        check_number(item, spec, item_key, number(item, item_key, false));
      }
      return;
    }
    }
  }

  /// Checks every key given in `table` (keys relative to `schema`), recursing into sub-tables.
  void check_given(toml::table& table, const Schema& schema, std::string_view schema_prefix,
                   std::string_view display_prefix) const
  {
    for (auto&& [k, node] : table) {
      const std::string key = join_key(schema_prefix, k.str());
      const std::string display_key = join_key(display_prefix, k.str());
      if (const KeySpec* spec = schema.find(key)) {
        check_value(node, *spec, display_key);
        if (spec->kind == ValueKind::table_list) {
          auto& array = *node.as_array();
          for (std::size_t i = 0; i < array.size(); ++i)
            validate_table(*array.get(i)->as_table(), *spec->element, fmt::format("{}[{}]", display_key, i));
        }
      } else if (node.is_table() && schema.has_table(key)) {
        check_given(*node.as_table(), schema, key, display_key);
      } else {
        const toml::source_region& region = k.source();
        std::string where = region.begin.line > 0
                                ? fmt::format("{}:{}", source_name(region, file), region.begin.line)
                                : node_location(&node, file);
        if (const std::string* why = schema.retired(key))
          throw InputError(where + ": " + display_key + ": " + *why);
        // A table ([fluuid] or fluuid.viscosity = ...) is compared with the table names.
        if (node.is_table())
          throw InputError(where + ": " + display_key + ": unknown table" +
                           table_suggestion(schema, schema_prefix, k.str(), display_prefix));
        throw InputError(where + ": " + display_key + ": unknown key" + suggestion(schema, key));
      }
    }
  }

  /// Sets aside the given keys that another given key makes unused (KeySpec::unused_with), with one
  /// warning naming them all, so that the case holds none of them.
  void set_aside_unused(toml::table& root, const Schema& schema, std::string_view display_prefix) const
  {
    std::string names, where, because;
    for (const auto& spec : schema.keys()) {
      toml::node* node = root.at_path(spec->key).node();
      if (spec->unused_with.empty() || !node || !root.at_path(spec->unused_with)) continue;
      if (names.empty()) where = node_location(node, file);
      names += (names.empty() ? "" : ", ") + join_key(display_prefix, spec->key);
      because = join_key(display_prefix, spec->unused_with);
      const auto dot = spec->key.rfind('.');
      toml::table* parent =
          dot == std::string::npos ? &root : root.at_path(spec->key.substr(0, dot)).as_table();
      parent->erase(spec->key.substr(dot == std::string::npos ? 0 : dot + 1));
    }
    if (!names.empty())
      warnings.push_back(where + ": " + names + ": not used with " + because + " (left out of the case)");
  }

  /// Reports a missing required key and inserts defaults for every other missing key (none for a key
  /// another given key makes unused).
  void complete(toml::table& root, const Schema& schema, std::string_view display_prefix) const
  {
    for (const auto& spec : schema.keys()) {
      if (root.at_path(spec->key)) continue;
      if (!spec->unused_with.empty() && root.at_path(spec->unused_with)) continue;
      if (spec->required)
        throw InputError(node_location(&root, file) + ": " + join_key(display_prefix, spec->key) +
                         ": missing required key (" + spec->doc + ")");
      if (!spec->default_value) continue;
      // Walk (and create) the tables leading to the key, then insert the default.
      toml::table* table = &root;
      std::string_view rest = spec->key;
      for (auto dot = rest.find('.'); dot != std::string_view::npos; dot = rest.find('.')) {
        const std::string part(rest.substr(0, dot));
        auto [it, inserted] = table->insert(part, toml::table{});
        (void)inserted;
        table = it->second.as_table();
        rest = rest.substr(dot + 1);
      }
      const std::string leaf(rest);
      std::visit(
          [&](const auto& v) {
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, bool> || std::is_same_v<T, std::int64_t> ||
                          std::is_same_v<T, double> || std::is_same_v<T, std::string>) {
              table->insert(leaf, v);
            } else {
              toml::array array;
              for (const auto& item : v) array.push_back(item);
              table->insert(leaf, std::move(array));
            }
          },
          *spec->default_value);
    }
  }

  void validate_table(toml::table& table, const Schema& schema, std::string_view display_prefix) const
  {
    check_given(table, schema, "", display_prefix);
    set_aside_unused(table, schema, display_prefix);
    complete(table, schema, display_prefix);
  }
};

} // namespace

namespace {

void flatten_into(const toml::node& node, const std::string& key,
                  std::vector<std::pair<std::string, std::string>>& out)
{
  if (const toml::table* table = node.as_table()) {
    for (auto&& [k, child] : *table)
      flatten_into(child, key.empty() ? std::string(k.str()) : key + "." + std::string(k.str()), out);
    return;
  }
  if (const toml::array* array = node.as_array(); array && !array->empty() && array->is_array_of_tables()) {
    for (std::size_t i = 0; i < array->size(); ++i)
      flatten_into((*array)[i], fmt::format("{}[{}]", key, i), out);
    return;
  }
  std::ostringstream os;
  node.visit([&](const auto& value) { os << value; });
  out.emplace_back(key, os.str());
}

} // namespace

std::vector<std::pair<std::string, std::string>> flattened(const toml::table& table)
{
  std::vector<std::pair<std::string, std::string>> out;
  flatten_into(table, "", out);
  return out;
}

toml::table parse_toml_file(const std::filesystem::path& file)
{
  check_input_file(file, max_text_bytes);
  try {
    return toml::parse_file(file.string());
  } catch (const toml::parse_error& error) {
    throw InputError(fmt::format("{}:{}: TOML syntax error: {}", file.string(), error.source().begin.line,
                                 std::string(error.description())));
  }
}

namespace {

std::string trimmed(std::string_view text)
{
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return "";
  const auto last = text.find_last_not_of(" \t");
  return std::string(text.substr(first, last - first + 1));
}

bool is_quoted(std::string_view value)
{
  return !value.empty() && (value.front() == '"' || value.front() == '\'');
}

/// A bare word as a TOML string (toml++ escapes it).
std::string toml_string(const std::string& word)
{
  std::ostringstream os;
  os << toml::value<std::string>(word);
  return os.str();
}

/// A string list given on the command line: bare elements quoted, quoted ones kept; a single bare
/// word is a list of one.
std::string quoted_list(const std::string& value)
{
  if (value.size() < 2 || value.front() != '[' || value.back() != ']') return "[" + toml_string(value) + "]";
  std::vector<std::string> items;
  std::string item;
  char quote = 0;
  for (char c : std::string_view(value).substr(1, value.size() - 2)) {
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == ',') {
      items.push_back(trimmed(item));
      item.clear();
      continue;
    }
    item += c;
  }
  if (!trimmed(item).empty() || !items.empty()) items.push_back(trimmed(item));
  std::string out = "[";
  for (std::size_t i = 0; i < items.size(); ++i)
    out += (i ? ", " : "") + (is_quoted(items[i]) ? items[i] : toml_string(items[i]));
  return out + "]";
}

/// One override's value as a TOML table holding its dotted key.
toml::table parse_override_value(const std::string& text, const KeyLookup& lookup)
{
  const auto equals = text.find('=');
  const std::string key = trimmed(std::string_view(text).substr(0, equals));
  const std::string value = trimmed(std::string_view(text).substr(equals + 1));
  const KeySpec* spec = lookup ? lookup(key) : nullptr;
  const std::string source = "command line (--set " + text + ")";
  std::string toml_text = text;
  if (spec && spec->kind == ValueKind::string && !is_quoted(value))
    toml_text = key + " = " + toml_string(value);
  else if (spec && spec->kind == ValueKind::string_list)
    toml_text = key + " = " + quoted_list(value);
  try {
    return toml::parse(toml_text, source);
  } catch (const toml::parse_error& error) {
    // A value that is no TOML (fluid.viscosity=abc) is kept as the word it is, so that validation
    // names the key and the type it expects; a broken list, table or string is a syntax error.
    const bool structured =
        !value.empty() && std::string_view("[{\"'").find(value.front()) != std::string::npos;
    if (!structured) {
      try {
        return toml::parse(key + " = " + toml_string(value), source);
      } catch (const toml::parse_error&) {
      }
    }
    throw InputError("command line: --set " + text + ": " + std::string(error.description()));
  }
}

/// One override as a TOML table holding its dotted key. A file it names (a path key, or each file of a
/// list of them) is named from the working folder, as a shell names it, and so written absolute (a case
/// file's own paths are read against the case file's folder).
toml::table parse_override(const std::string& text, const KeyLookup& lookup)
{
  toml::table parsed = parse_override_value(text, lookup);
  const std::string key = trimmed(std::string_view(text).substr(0, text.find('=')));
  const KeySpec* spec = lookup ? lookup(key) : nullptr;
  toml::node* node = parsed.at_path(key).node();
  if (!spec || !spec->is_path || !node) return parsed;
  const auto absolute = [](toml::node& item) {
    if (const auto* name = item.as_string(); name && !name->get().empty())
      item.as_string()->get() = std::filesystem::absolute(name->get()).lexically_normal().string();
  };
  if (toml::array* files = node->as_array())
    for (toml::node& item : *files) absolute(item);
  else
    absolute(*node);
  return parsed;
}

} // namespace

void apply_overrides(toml::table& table, std::span<const std::string> overrides, const KeyLookup& lookup)
{
  for (const std::string& text : overrides) {
    const auto equals = text.find('=');
    // One key per --set: a line break would let one override smuggle in further keys (and lines
    // into config.toml).
    if (text.find_first_of("\n\r") != std::string::npos) {
      std::string shown = text.substr(0, text.find_first_of("\n\r"));
      throw InputError("command line: --set " + shown +
                       "...: a line break in an override (one key=value each)");
    }
    if (equals == std::string::npos || equals == 0)
      throw InputError("command line: --set " + text + ": expected key=value");
    toml::table parsed = parse_override(text, lookup);
    // Merge the parsed dotted key into the file's tables, replacing any value given there.
    std::function<void(toml::table&, toml::table&)> merge = [&](toml::table& into, toml::table& from) {
      for (auto&& [k, node] : from) {
        toml::node* existing = into.get(k.str());
        if (node.is_table() && existing && existing->is_table())
          merge(*existing->as_table(), *node.as_table());
        else
          into.insert_or_assign(k.str(), std::move(node));
      }
    };
    merge(table, parsed);
  }
}

Config Config::validate(toml::table table, const std::filesystem::path& file, const Schema& schema)
{
  std::vector<std::string> warnings;
  Validator{file, warnings}.validate_table(table, schema, "");
  auto state = std::make_shared<State>(State{std::move(table), file, schema, std::move(warnings)});
  const State* raw = state.get();
  return Config(std::move(state), &raw->root, &raw->schema, "");
}

Config Config::load(const std::filesystem::path& file, const Schema& schema,
                    std::span<const std::string> overrides)
{
  toml::table table = parse_toml_file(file);
  apply_overrides(table, overrides, [&](std::string_view key) { return schema.find(key); });
  return validate(std::move(table), file, schema);
}

// ---------------------------------------------------------------------------------------------
// Access

const KeySpec& Config::spec(std::string_view key) const
{
  const KeySpec* s = schema_->find(key);
  if (!s) throw std::logic_error("Config: key not in schema: " + std::string(key));
  return *s;
}

const toml::node* Config::node(std::string_view key) const
{
  spec(key);
  return table_->at_path(key).node();
}

bool Config::has(std::string_view key) const
{
  return node(key) != nullptr;
}

namespace {
const toml::node& require(const toml::node* n, std::string_view key)
{
  if (!n) throw std::logic_error("Config: optional key read without a value: " + std::string(key));
  return *n;
}

double number_of(const toml::node& n)
{
  return n.is_integer() ? static_cast<double>(*n.value<std::int64_t>()) : *n.value<double>();
}
} // namespace

bool Config::boolean(std::string_view key) const
{
  return *require(node(key), key).value<bool>();
}

std::int64_t Config::integer(std::string_view key) const
{
  return *require(node(key), key).value<std::int64_t>();
}

double Config::real(std::string_view key) const
{
  return number_of(require(node(key), key)) * *units::to_cgs(spec(key).unit);
}

std::string Config::string(std::string_view key) const
{
  return *require(node(key), key).value<std::string>();
}

std::filesystem::path Config::path(std::string_view key) const
{
  std::filesystem::path p(string(key));
  return p.is_relative() ? state_->file.parent_path() / p : p;
}

std::vector<std::filesystem::path> Config::paths(std::string_view key) const
{
  std::vector<std::filesystem::path> out;
  for (const std::string& name : strings(key)) {
    const std::filesystem::path p(name);
    out.push_back(p.is_relative() ? state_->file.parent_path() / p : p);
  }
  return out;
}

std::vector<double> Config::reals(std::string_view key) const
{
  const double factor = *units::to_cgs(spec(key).unit);
  std::vector<double> out;
  for (const auto& item : *require(node(key), key).as_array()) out.push_back(number_of(item) * factor);
  return out;
}

std::vector<std::int64_t> Config::integers(std::string_view key) const
{
  std::vector<std::int64_t> out;
  for (const auto& item : *require(node(key), key).as_array()) out.push_back(*item.value<std::int64_t>());
  return out;
}

std::vector<std::string> Config::strings(std::string_view key) const
{
  std::vector<std::string> out;
  for (const auto& item : *require(node(key), key).as_array()) out.push_back(*item.value<std::string>());
  return out;
}

std::vector<std::pair<std::string, double>> Config::named_reals(std::string_view key) const
{
  std::vector<std::pair<std::string, double>> out;
  const toml::node* n = node(key);
  if (!n) return out;
  for (auto&& [name, item] : *n->as_table())
    out.emplace_back(std::string(name.str()), item.is_integer()
                                                  ? static_cast<double>(*item.value<std::int64_t>())
                                                  : *item.value<double>());
  return out;
}

std::vector<Config> Config::tables(std::string_view key) const
{
  std::vector<Config> out;
  const KeySpec& s = spec(key);
  const toml::node* n = node(key);
  if (!n) return out;
  const auto& array = *n->as_array();
  for (std::size_t i = 0; i < array.size(); ++i)
    out.push_back(Config(state_, array.get(i)->as_table(), s.element.get(),
                         fmt::format("{}[{}]", join_key(prefix_, key), i)));
  return out;
}

std::string Config::where(std::string_view key) const
{
  const toml::node* n = table_->at_path(key).node();
  return node_location(n, state_->file);
}

void Config::fail(std::string_view key, std::string_view message) const
{
  throw InputError(where(key) + ": " + join_key(prefix_, key) + ": " + std::string(message));
}
} // namespace ibvalve::io
