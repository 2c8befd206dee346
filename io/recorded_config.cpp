#include "io/recorded_config.hpp"

#include <fmt/format.h>
#include <sstream>

#include <toml++/toml.h>

#include "io/config.hpp"
#include "io/files.hpp"

namespace ibvalve::io {

namespace {

/// A value as a reader is shown it (RecordedEntry::value).
std::string readable(const toml::node& node)
{
  if (const auto* x = node.as_floating_point()) {
    const double v = x->get();
    return fmt::format("{}", v == 0.0 ? 0.0 : v); // -0.0 reads as a sign that is not there
  }
  if (const auto* n = node.as_integer()) return fmt::format("{}", n->get());
  if (const auto* list = node.as_array()) {
    std::string text;
    for (const auto& item : *list) text += (text.empty() ? "" : ", ") + readable(item);
    return "[" + text + "]";
  }
  std::ostringstream os;
  node.visit([&](const auto& value) { os << value; });
  return os.str();
}

/// The unit of the comment after a value on its line: "  # [unit] meaning" or, for a value a preset
/// supplies, "  # from KEY = "NAME"; [unit] meaning" (Config::resolved_toml).
std::string unit_of(const std::string& line, const toml::source_region& where)
{
  const std::size_t from = where.end.column > 0 ? static_cast<std::size_t>(where.end.column - 1) : 0;
  const std::size_t hash = from < line.size() ? line.find('#', from) : std::string::npos;
  if (hash == std::string::npos) return "";
  std::string comment = trim(std::string_view(line).substr(hash + 1));
  if (comment.starts_with("from ")) {
    const std::size_t semicolon = comment.find("; ");
    comment = semicolon == std::string::npos ? "" : comment.substr(semicolon + 2);
  }
  const std::size_t close = comment.find(']');
  return comment.starts_with('[') && close != std::string::npos ? comment.substr(1, close - 1) : "";
}

void collect(const toml::node& node, const std::string& key, const std::vector<std::string>& lines,
             std::vector<RecordedEntry>& out)
{
  if (const toml::table* table = node.as_table()) {
    for (auto&& [k, child] : *table)
      collect(child, key.empty() ? std::string(k.str()) : key + "." + std::string(k.str()), lines, out);
    return;
  }
  if (const toml::array* array = node.as_array(); array && !array->empty() && array->is_array_of_tables()) {
    for (std::size_t i = 0; i < array->size(); ++i)
      collect((*array)[i], fmt::format("{}[{}]", key, i), lines, out);
    return;
  }
  const auto& where = node.source();
  const std::size_t line = where.end.line > 0 ? static_cast<std::size_t>(where.end.line - 1) : lines.size();
  out.push_back({key, readable(node), line < lines.size() ? unit_of(lines[line], where) : ""});
}

} // namespace

std::vector<RecordedEntry> read_recorded_config(const std::filesystem::path& config_file)
{
  const toml::table table = parse_toml_file(config_file);
  std::vector<std::string> lines;
  std::istringstream text(read_text_file(config_file));
  for (std::string line; std::getline(text, line);) lines.push_back(line);
  std::vector<RecordedEntry> out;
  collect(table, "", lines, out);
  return out;
}

} // namespace ibvalve::io
