// The schema of a case file: its keys' kinds, units, defaults, ranges and documentation (io/config.hpp),
// listed as Markdown (`ibvalve keys`) and as a commented TOML skeleton (`ibvalve keys --format toml`).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <fmt/format.h>
#include <sstream>
#include <stdexcept>

#include "base/units.hpp"
#include "io/config.hpp"
#include "io/schema_text.hpp"

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

namespace detail {

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

} // namespace detail

using namespace detail; // the text helpers the schema, validation and writing share

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
} // namespace ibvalve::io
