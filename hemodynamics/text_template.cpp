#include "hemodynamics/text_template.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <fmt/format.h>
#include <vector>

#include "base/errors.hpp"
#include "io/files.hpp"

namespace ibvalve::hemodynamics {

namespace {

/// Starts every line that is not standalone; never in a report's text (an ASCII control character).
constexpr char line_marker = '\x1f';

struct Token {
  std::string_view text;
  bool is_tag = false;
};

/// Text and tags ({{...}} or {{{...}}}); the text has been parsed, so every tag is closed.
std::vector<Token> tokens(std::string_view text)
{
  std::vector<Token> out;
  std::size_t pos = 0;
  while (pos < text.size()) {
    const std::size_t open = text.find("{{", pos);
    if (open == std::string_view::npos) {
      out.push_back({text.substr(pos)});
      break;
    }
    if (open > pos) out.push_back({text.substr(pos, open - pos)});
    const bool triple = text.substr(open, 3) == "{{{";
    const std::size_t close = text.find(triple ? "}}}" : "}}", open + 2);
    const std::size_t end = close == std::string_view::npos ? text.size() : close + (triple ? 3 : 2);
    out.push_back({text.substr(open, end - open), true});
    pos = end;
  }
  return out;
}

/// The tag's sigil: '#', '^', '/', '!', '>', '=', '{', '&', or ' ' for a plain variable.
char sigil(std::string_view tag)
{
  const auto first = tag.find_first_not_of(" \t", 2);
  if (first == std::string_view::npos) return ' ';
  const char c = tag[first];
  return std::string_view("#^/!>={&").find(c) == std::string_view::npos ? ' ' : c;
}

bool blank(std::string_view s)
{
  return std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isspace(c); });
}

/// The text with standalone lines reduced to their tag and every other line led by line_marker.
std::string prepared(std::string_view text)
{
  std::string out;
  std::vector<Token> line; // the tokens of one line, its line break included
  auto flush = [&] {
    int tags = 0, standalone_tags = 0;
    bool only_blanks = true;
    for (const Token& t : line) {
      if (t.is_tag) {
        ++tags;
        standalone_tags += std::string_view("#^/!").find(sigil(t.text)) != std::string_view::npos;
      } else {
        only_blanks = only_blanks && blank(t.text);
      }
    }
    if (tags == 1 && standalone_tags == 1 && only_blanks) {
      for (const Token& t : line)
        if (t.is_tag) out += t.text;
    } else if (!line.empty()) {
      out += line_marker;
      for (const Token& t : line) out += t.text;
    }
    line.clear();
  };
  for (const Token& t : tokens(text)) {
    if (t.is_tag) {
      line.push_back(t);
      continue;
    }
    std::size_t pos = 0;
    for (std::size_t nl = t.text.find('\n'); nl != std::string_view::npos; nl = t.text.find('\n', pos)) {
      line.push_back({t.text.substr(pos, nl + 1 - pos)});
      flush();
      pos = nl + 1;
    }
    if (pos < t.text.size()) line.push_back({t.text.substr(pos)});
  }
  flush();
  return out;
}

/// "origin:LINE: what" from kainjow's "what at OFFSET" (the offset into `text`).
std::string located(const std::string& origin, std::string_view text, const std::string& message)
{
  const std::size_t at = message.rfind(" at ");
  std::size_t offset = 0;
  if (at != std::string::npos) {
    const char* first = message.data() + at + 4;
    const char* last = message.data() + message.size();
    if (auto [ptr, ec] = std::from_chars(first, last, offset); ec == std::errc() && ptr == last) {
      const auto line = 1 + std::count(text.begin(), text.begin() + std::min(offset, text.size()), '\n');
      return fmt::format("{}:{}: {}", origin, line, message.substr(0, at));
    }
  }
  return origin + ": " + message;
}

/// The text made ready for kainjow (prepared()), after checking it as written (so that an error names
/// the line of the file).
std::string checked_and_prepared(std::string_view text, const std::string& origin)
{
  std::string source(text);
  std::erase(source, line_marker);
  const kainjow::mustache::mustache as_written(source);
  if (!as_written.is_valid())
    throw InputError(located(origin, source, as_written.error_message()) +
                     " (not a valid Mustache template)");
  const std::vector<Token> all = tokens(source);
  if (std::any_of(all.begin(), all.end(), [](const Token& t) { return t.is_tag && sigil(t.text) == '='; }))
    throw InputError(origin + ": set-delimiter tags ({{=...=}}) are not supported");
  return prepared(source);
}

} // namespace

std::string markdown_escaped(std::string_view text)
{
  std::string out;
  for (char c : io::xml_escaped(text)) {
    if (c == '|')
      out += "\\|";
    else
      out += (c == '\n' || c == '\r') ? ' ' : c;
  }
  return out;
}

TextTemplate::TextTemplate(std::string_view text, std::string origin, Escaping escaping)
    : origin_(std::move(origin)), template_(checked_and_prepared(text, origin_))
{
  if (!template_.is_valid()) throw InputError(origin_ + ": " + template_.error_message());
  // Names come from a user's files (case names, mesh groups): in Markdown, which passes HTML through, a
  // '<' could start a tag and a '|' end a table cell.
  if (escaping == Escaping::markdown)
    template_.set_custom_escape([](const std::string& s) { return markdown_escaped(s); });
  if (escaping == Escaping::html)
    template_.set_custom_escape([](const std::string& s) { return io::xml_escaped(s); });
}

std::string TextTemplate::render(const kainjow::mustache::data& values) const
{
  std::string out = template_.render(values);
  if (!template_.is_valid()) throw InputError(origin_ + ": " + template_.error_message());
  std::erase(out, line_marker);
  return out;
}

} // namespace ibvalve::hemodynamics
