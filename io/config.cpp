#include "io/config.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fmt/format.h>
#include <functional>
#include <sstream>
#include <stdexcept>

#include "base/errors.hpp"
#include "base/units.hpp"
#include "io/files.hpp"

namespace ibvalve::io {

// ---------------------------------------------------------------------------------------------
// Schema

KeyBuilder& KeyBuilder::unit(std::string unit)
{
  if (!units::to_cgs(unit))
    throw std::logic_error("schema key " + spec_->key + ": unknown unit '" + unit + "'");
  spec_->unit = std::move(unit);
  return *this;
}

KeyBuilder& KeyBuilder::required()
{
  spec_->required = true;
  return *this;
}

KeyBuilder& KeyBuilder::defaults(Value value)
{
  spec_->default_value = std::move(value);
  return *this;
}

KeyBuilder& KeyBuilder::example(Value value)
{
  spec_->example = std::move(value);
  return *this;
}

KeyBuilder& KeyBuilder::at_least(double min)
{
  spec_->min = min;
  spec_->min_inclusive = true;
  return *this;
}

KeyBuilder& KeyBuilder::above(double min)
{
  spec_->min = min;
  spec_->min_inclusive = false;
  return *this;
}

KeyBuilder& KeyBuilder::at_most(double max)
{
  spec_->max = max;
  spec_->max_inclusive = true;
  return *this;
}

KeyBuilder& KeyBuilder::below(double max)
{
  spec_->max = max;
  spec_->max_inclusive = false;
  return *this;
}

KeyBuilder& KeyBuilder::choices(std::vector<std::string> allowed)
{
  spec_->choices = std::move(allowed);
  return *this;
}

KeyBuilder& KeyBuilder::sizes(std::size_t min, std::size_t max)
{
  spec_->min_size = min;
  spec_->max_size = max;
  return *this;
}

KeyBuilder& KeyBuilder::file(bool must_exist)
{
  spec_->is_path = true;
  spec_->must_exist = must_exist;
  return *this;
}

KeyBuilder& KeyBuilder::unused_with(std::string key)
{
  spec_->doc += " (not used with " + key + ")";
  spec_->unused_with = std::move(key);
  return *this;
}

KeyBuilder& KeyBuilder::typical(double lo, double hi, std::string why)
{
  spec_->typical_min = lo;
  spec_->typical_max = hi;
  spec_->typical_why = std::move(why);
  return *this;
}

KeyBuilder& KeyBuilder::preset(std::string preset_key,
                               std::function<std::optional<Value>(const std::string&)> value)
{
  spec_->preset_key = std::move(preset_key);
  spec_->from_preset = std::move(value);
  return *this;
}

KeyBuilder Schema::add(std::string key, ValueKind kind, std::string doc)
{
  if (find(key)) throw std::logic_error("schema key defined twice: " + key);
  auto spec = std::make_unique<KeySpec>();
  spec->key = std::move(key);
  spec->kind = kind;
  spec->doc = std::move(doc);
  keys_.push_back(std::move(spec));
  return KeyBuilder(*keys_.back());
}

KeyBuilder Schema::add_boolean(std::string key, std::string doc)
{
  return add(std::move(key), ValueKind::boolean, std::move(doc));
}
KeyBuilder Schema::add_integer(std::string key, std::string doc)
{
  return add(std::move(key), ValueKind::integer, std::move(doc));
}
KeyBuilder Schema::add_real(std::string key, std::string doc)
{
  return add(std::move(key), ValueKind::real, std::move(doc));
}
KeyBuilder Schema::add_string(std::string key, std::string doc)
{
  return add(std::move(key), ValueKind::string, std::move(doc));
}
KeyBuilder Schema::add_real_list(std::string key, std::string doc)
{
  return add(std::move(key), ValueKind::real_list, std::move(doc));
}
KeyBuilder Schema::add_integer_list(std::string key, std::string doc)
{
  return add(std::move(key), ValueKind::integer_list, std::move(doc));
}
KeyBuilder Schema::add_real_table(std::string key, std::string doc)
{
  return add(std::move(key), ValueKind::real_table, std::move(doc));
}

KeyBuilder Schema::add_string_list(std::string key, std::string doc)
{
  return add(std::move(key), ValueKind::string_list, std::move(doc));
}

KeyBuilder Schema::add_table_list(std::string key, Schema element, std::string doc)
{
  auto builder = add(std::move(key), ValueKind::table_list, std::move(doc));
  keys_.back()->element = std::make_shared<const Schema>(std::move(element));
  return builder;
}

void Schema::retire(std::string key, std::string why)
{
  if (find(key) || retired(key)) throw std::logic_error("schema key defined twice: " + key);
  retired_.emplace_back(std::move(key), std::move(why));
}

const std::string* Schema::retired(std::string_view key) const
{
  for (const auto& [name, why] : retired_)
    if (name == key) return &why;
  return nullptr;
}

void Schema::merge(const Schema& other)
{
  for (const auto& spec : other.keys_) {
    if (find(spec->key) || retired(spec->key))
      throw std::logic_error("schema key defined twice: " + spec->key);
    keys_.push_back(std::make_unique<KeySpec>(*spec));
  }
  for (const auto& [key, why] : other.retired_) retire(key, why);
}

Schema& Schema::operator=(const Schema& other)
{
  if (this != &other) {
    keys_.clear();
    retired_.clear();
    merge(other);
  }
  return *this;
}

const KeySpec* Schema::find(std::string_view key) const
{
  for (const auto& spec : keys_)
    if (spec->key == key) return spec.get();
  return nullptr;
}

bool Schema::has_table(std::string_view prefix) const
{
  for (const auto& spec : keys_)
    if (spec->key.size() > prefix.size() && spec->key.starts_with(prefix) && spec->key[prefix.size()] == '.')
      return true;
  return false;
}

namespace {

std::string kind_name(ValueKind kind)
{
  switch (kind) {
  case ValueKind::boolean:
    return "true or false";
  case ValueKind::integer:
    return "an integer";
  case ValueKind::real:
    return "a number";
  case ValueKind::string:
    return "a string";
  case ValueKind::real_list:
    return "a list of numbers";
  case ValueKind::integer_list:
    return "a list of integers";
  case ValueKind::string_list:
    return "a list of strings";
  case ValueKind::table_list:
    return "a list of tables ([[...]])";
  case ValueKind::real_table:
    return "a table of numbers ({ name = number, ... })";
  }
  return "?";
}

/// The shortest text that reads back as `x` (no ".0" added: for messages and tables).
std::string format_number(double x)
{
  char buffer[64];
  const auto [end, error] = std::to_chars(buffer, buffer + sizeof buffer, x);
  if (error != std::errc{}) return "?";
  return std::string(buffer, end);
}

std::string join_key(std::string_view prefix, std::string_view key)
{
  return prefix.empty() ? std::string(key) : std::string(prefix) + "." + std::string(key);
}

std::string range_text(const KeySpec& s)
{
  std::string text;
  const bool has_min = std::isfinite(s.min), has_max = std::isfinite(s.max);
  if (has_min && has_max)
    text = std::string(s.min_inclusive ? "[" : "(") + format_number(s.min) + ", " + format_number(s.max) +
           (s.max_inclusive ? "]" : ")");
  else if (has_min)
    text = std::string(s.min_inclusive ? ">= " : "> ") + format_number(s.min);
  else if (has_max)
    text = std::string(s.max_inclusive ? "<= " : "< ") + format_number(s.max);
  if (!text.empty() && !s.unit.empty()) text += " " + s.unit;
  return text;
}

std::string join(const std::vector<std::string>& items, std::string_view separator)
{
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) out += (i ? std::string(separator) : "") + items[i];
  return out;
}

/// "typical 1-20 cP" for a key with a typical range ("" otherwise).
std::string typical_text(const KeySpec& s)
{
  const bool has_min = std::isfinite(s.typical_min), has_max = std::isfinite(s.typical_max);
  std::string text;
  if (has_min && has_max)
    text = format_number(s.typical_min) + " to " + format_number(s.typical_max);
  else if (has_min)
    text = "at least " + format_number(s.typical_min);
  else if (has_max)
    text = "at most " + format_number(s.typical_max);
  if (!text.empty() && !s.unit.empty()) text += " " + s.unit;
  return text;
}

} // namespace

std::string format_real(double x)
{
  std::string text = format_number(x);
  if (std::isfinite(x) && text.find_first_of(".eE") == std::string::npos) text += ".0";
  return text;
}

namespace {

/// A schema value as TOML text.
std::string value_text(const Value& value)
{
  auto scalar = [](const auto& v) -> std::string {
    using T = std::decay_t<decltype(v)>;
    if constexpr (std::is_same_v<T, double>) {
      return format_real(v);
    } else {
      std::ostringstream os;
      os << toml::value<T>(v);
      return os.str();
    }
  };
  return std::visit(
      [&](const auto& v) -> std::string {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, bool> || std::is_same_v<T, std::int64_t> ||
                      std::is_same_v<T, double> || std::is_same_v<T, std::string>) {
          return scalar(v);
        } else {
          std::string out = "[";
          for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + scalar(v[i]);
          return out + "]";
        }
      },
      value);
}

/// "[unit] meaning; allowed ...; typical ..." for a skeleton's comment.
std::string skeleton_comment(const KeySpec& spec)
{
  std::string c = spec.unit.empty() ? "" : "[" + spec.unit + "] ";
  c += spec.doc;
  const std::string allowed = spec.choices.empty() ? range_text(spec) : join(spec.choices, ", ");
  if (!allowed.empty()) c += "; allowed: " + allowed;
  if (const std::string typical = typical_text(spec); !typical.empty()) c += "; typical " + typical;
  return c;
}

/// One key of a skeleton: at its default, at its example (required keys), else commented out.
using Fixed = std::span<const std::pair<std::string, Value>>;

std::string skeleton_line(const KeySpec& spec, const std::string& name, std::string_view comment_out,
                          Fixed fixed)
{
  const std::string comment = "  # " + skeleton_comment(spec);
  for (const auto& [key, value] : fixed)
    if (key == spec.key) return std::string(comment_out) + name + " = " + value_text(value) + comment;
  if (spec.default_value)
    return std::string(comment_out) + name + " = " + value_text(*spec.default_value) + comment;
  if (spec.example)
    return std::string(comment_out) + name + " = " + value_text(*spec.example) +
           (spec.required ? "  # REQUIRED (an example value); " : "  # an example value (no default); ") +
           skeleton_comment(spec);
  if (spec.required) return "# " + name + " =   # REQUIRED; " + skeleton_comment(spec);
  if (!spec.preset_key.empty())
    return "# " + name + " =   # optional; else from " + spec.preset_key + "; " + skeleton_comment(spec);
  return "# " + name + " =   # optional, no default; " + skeleton_comment(spec);
}

void write_skeleton(std::ostringstream& os, const Schema& schema, std::string_view header_prefix,
                    std::string_view comment_out, Fixed fixed)
{
  std::vector<std::string> sections;
  for (const auto& spec : schema.keys()) {
    if (spec->kind == ValueKind::table_list) continue;
    const auto dot = spec->key.find('.');
    if (dot == std::string::npos)
      os << skeleton_line(*spec, spec->key, comment_out, fixed) << "\n";
    else if (std::find(sections.begin(), sections.end(), spec->key.substr(0, dot)) == sections.end())
      sections.push_back(spec->key.substr(0, dot));
  }
  for (const std::string& section : sections) {
    os << "\n" << comment_out << "[" << join_key(header_prefix, section) << "]\n";
    for (const auto& spec : schema.keys())
      if (spec->kind != ValueKind::table_list && spec->key.starts_with(section + "."))
        os << skeleton_line(*spec, spec->key.substr(section.size() + 1), comment_out, fixed) << "\n";
  }
  // A table list has no default: one element shown, commented out.
  for (const auto& spec : schema.keys()) {
    if (spec->kind != ValueKind::table_list) continue;
    const std::string name = join_key(header_prefix, spec->key);
    os << "\n# [[" << name << "]]  # " << spec->doc << " (repeat the block for each; none by default)\n";
    write_skeleton(os, *spec->element, name, "# ", {});
  }
}

} // namespace

std::string Schema::toml_skeleton(std::string_view head,
                                  std::span<const std::pair<std::string, Value>> fixed) const
{
  std::ostringstream os;
  os << head;
  write_skeleton(os, *this, "", "", fixed);
  return os.str();
}

std::string Schema::markdown() const
{
  std::ostringstream os;
  os << "| key | type | unit | default | allowed | meaning |\n|---|---|---|---|---|---|\n";
  for (const auto& spec : keys_) {
    std::string def = "";
    if (spec->required) def = "(required)";
    if (spec->default_value) {
      std::visit(
          [&](const auto& v) {
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, bool>)
              def = v ? "true" : "false";
            else if constexpr (std::is_same_v<T, std::int64_t>)
              def = fmt::to_string(v);
            else if constexpr (std::is_same_v<T, double>)
              def = format_number(v);
            else if constexpr (std::is_same_v<T, std::string>)
              def = "\"" + v + "\"";
            else
              def = "[...]";
          },
          *spec->default_value);
    }
    std::string allowed = spec->choices.empty() ? range_text(*spec) : join(spec->choices, ", ");
    if (const std::string typical = typical_text(*spec); !typical.empty())
      allowed += (allowed.empty() ? "" : "; ") + std::string("typical ") + typical;
    if (!spec->preset_key.empty() && def.empty()) def = "(from `" + spec->preset_key + "`)";
    os << "| `" << spec->key << "` | " << kind_name(spec->kind) << " | " << spec->unit << " | " << def
       << " | " << allowed << " | " << spec->doc << " |\n";
    if (spec->element) {
      std::istringstream inner(spec->element->markdown());
      std::string line;
      std::getline(inner, line);
      std::getline(inner, line);
      while (std::getline(inner, line)) {
        const auto tick = line.find('`');
        if (tick != std::string::npos) line.insert(tick + 1, spec->key + "[]."); // element keys
        os << line << "\n";
      }
    }
  }
  return os.str();
}

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

// ---------------------------------------------------------------------------------------------
// Writing

namespace {

/// A value as TOML; floats in their shortest exact form (2e-05, not 2.0000000000000002e-05).
std::string format_node(const toml::node& node)
{
  if (const auto* x = node.as_floating_point()) return format_real(x->get());
  if (const auto* array = node.as_array()) {
    std::string out = "[";
    for (std::size_t i = 0; i < array->size(); ++i) out += (i ? ", " : "") + format_node(*array->get(i));
    return out + "]";
  }
  if (const auto* table = node.as_table()) { // an inline table (a real_table key)
    std::string out;
    for (auto&& [name, item] : *table)
      out += (out.empty() ? "{ " : ", ") + std::string(name.str()) + " = " + format_node(item);
    return out.empty() ? "{}" : out + " }";
  }
  std::ostringstream os;
  node.visit([&](const auto& v) { os << v; });
  return os.str();
}

/// A value a preset supplies, as the case file writes it: a real converted from CGS to the key's unit.
/// Nothing when the converted value would not read back as exactly the value the run uses (then the
/// preset stays in charge and the value goes into a comment).
std::optional<std::string> format_preset_value(const Value& value, const KeySpec& spec)
{
  const double factor = *units::to_cgs(spec.unit);
  // Of the doubles next to cgs / factor, the shortest that reads back (times the factor) exactly.
  auto exact = [&](double cgs) -> std::optional<std::string> {
    double x = cgs / factor;
    for (int i = 0; i < 3; ++i) x = std::nextafter(x, -HUGE_VAL);
    std::optional<std::string> best;
    for (int i = 0; i < 7; ++i, x = std::nextafter(x, HUGE_VAL)) {
      const std::string text = format_real(x);
      if (x * factor == cgs && (!best || text.size() < best->size())) best = text;
    }
    return best;
  };
  return std::visit(
      [&](const auto& v) -> std::optional<std::string> {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, double>) {
          return exact(v);
        } else if constexpr (std::is_same_v<T, std::vector<double>>) {
          std::string out = "[";
          for (std::size_t i = 0; i < v.size(); ++i) {
            const auto item = exact(v[i]);
            if (!item) return std::nullopt;
            out += (i ? ", " : "") + *item;
          }
          return out + "]";
        } else if constexpr (std::is_same_v<T, bool> || std::is_same_v<T, std::int64_t> ||
                             std::is_same_v<T, std::string>) {
          return format_node(toml::value<T>(v));
        } else {
          toml::array array;
          for (const auto& item : v) array.push_back(item);
          return format_node(array);
        }
      },
      value);
}

/// The line for a key the case does not give: the preset's value where a preset supplies it, else
/// "(not set)" in a comment.
std::string unset_line(const toml::table& table, const KeySpec& spec, const std::string& name,
                       const std::string& comment)
{
  if (spec.from_preset) {
    const toml::node* preset = table.at_path(spec.preset_key).node();
    if (preset && preset->is_string()) {
      const std::string preset_name = *preset->value<std::string>();
      if (const std::optional<Value> value = spec.from_preset(preset_name)) {
        const std::string from =
            "  # from " + spec.preset_key + " = \"" + preset_name + "\";" + comment.substr(3);
        if (const auto text = format_preset_value(*value, spec)) return name + " = " + *text + from + "\n";
        // Not exactly representable in the key's unit: kept to the preset (a shortest decimal here).
        const double* x = std::get_if<double>(&*value);
        return "# " + name + " = " + (x ? format_number(*x / *units::to_cgs(spec.unit)) : "...") + from +
               "\n";
      }
    }
  }
  return "# " + name + " = (not set)" + comment + "\n";
}

/// How the file paths of a resolved configuration are written: read against the case file's folder,
/// then absolute, or relative to `written_in` when it is given (the folder the file goes into, so that a
/// run folder's config.toml names the same files from where it lies, on any machine).
struct PathWriting {
  std::filesystem::path case_folder;
  std::filesystem::path written_in;

  std::string operator()(const std::string& name) const
  {
    const std::filesystem::path path(name);
    if (path.empty()) return name;
    const auto absolute = std::filesystem::absolute(case_folder / path).lexically_normal();
    if (written_in.empty()) return path.is_relative() ? absolute.string() : name;
    const auto relative =
        absolute.lexically_relative(std::filesystem::absolute(written_in).lexically_normal());
    return relative.empty() ? absolute.string() : relative.string();
  }
};

/// A value as written, except that a file path is written as `paths` says, so that a run folder's
/// config.toml still names the same files (`ibvalve run --restart`).
std::string format_value(const toml::node& node, const KeySpec& spec, const PathWriting& paths)
{
  if (spec.is_path && node.is_string())
    return format_node(toml::value<std::string>(paths(*node.value<std::string>())));
  if (spec.is_path && node.is_array()) { // a list of files (KeyBinder::paths)
    toml::array files;
    for (const auto& item : *node.as_array())
      files.push_back(item.is_string() ? paths(*item.value<std::string>()) : std::string());
    return format_node(files);
  }
  return format_node(node);
}

/// Writes the keys of `schema` found in `table`: plain keys as dotted keys under a [section] per first
/// component, table lists as [[...]] blocks. Units and meanings go into comments.
void write_table(std::ostringstream& os, const toml::table& table, const Schema& schema,
                 std::string_view header_prefix, const PathWriting& paths)
{
  auto comment = [](const KeySpec& spec) {
    std::string c = spec.unit.empty() ? "" : "[" + spec.unit + "] ";
    return "  # " + c + spec.doc;
  };
  // Root-level keys first (TOML puts everything before the first header into the root table).
  std::vector<std::string> sections;
  for (const auto& spec : schema.keys()) {
    if (spec->kind == ValueKind::table_list) continue;
    const auto dot = spec->key.find('.');
    if (dot == std::string::npos) {
      if (const toml::node* n = table.get(spec->key))
        os << spec->key << " = " << format_value(*n, *spec, paths) << comment(*spec) << "\n";
    } else if (std::find(sections.begin(), sections.end(), spec->key.substr(0, dot)) == sections.end()) {
      sections.push_back(spec->key.substr(0, dot));
    }
  }
  for (const std::string& section : sections) {
    os << "\n[" << join_key(header_prefix, section) << "]\n";
    for (const auto& spec : schema.keys()) {
      if (spec->kind == ValueKind::table_list || !spec->key.starts_with(section + ".")) continue;
      const std::string rest = spec->key.substr(section.size() + 1);
      if (const toml::node* n = table.at_path(spec->key).node())
        os << rest << " = " << format_value(*n, *spec, paths) << comment(*spec) << "\n";
      else if (spec->unused_with.empty() || !table.at_path(spec->unused_with))
        os << unset_line(table, *spec, rest, comment(*spec));
    }
  }
  for (const auto& spec : schema.keys()) {
    if (spec->kind != ValueKind::table_list) continue;
    const toml::node* n = table.at_path(spec->key).node();
    if (!n) continue;
    for (const auto& element : *n->as_array()) {
      const std::string name = join_key(header_prefix, spec->key);
      os << "\n[[" << name << "]]  # " << spec->doc << "\n";
      std::ostringstream inner;
      write_table(inner, *element.as_table(), *spec->element, name, paths);
      os << inner.str();
    }
  }
}

} // namespace

std::string Config::resolved_toml(const std::filesystem::path& written_in) const
{
  const PathWriting paths{state_->file.parent_path(), written_in};
  std::ostringstream os;
  os << "# Resolved configuration: every key, defaults written out. Read from "
     << (written_in.empty() ? state_->file.string() : paths(state_->file.filename().string())) << "\n";
  write_table(os, *table_, *schema_, "", paths);
  return os.str();
}

} // namespace ibvalve::io
