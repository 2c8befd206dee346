// A validated case written back as TOML (Config::resolved_toml): every key, defaults and a preset's values
// written out, units and meanings in comments, file paths as the folder written into reads them.
#include <cmath>
#include <optional>
#include <sstream>
#include <string>

#include "base/units.hpp"
#include "io/config.hpp"
#include "io/schema_text.hpp"

namespace ibvalve::io {

using detail::format_number;
using detail::join_key;

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
      // The walk steps over +0 (from -0 to the smallest positive double): zero is written unsigned.
      const double candidate = x == 0 ? 0.0 : x;
      const std::string text = format_real(candidate);
      if (candidate * factor == cgs && (!best || text.size() < best->size())) best = text;
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
