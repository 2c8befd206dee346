#include "hemodynamics/json.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace ibvalve::hemodynamics {

std::string json_number(double x)
{
  if (!std::isfinite(x)) return "null";
  // The shortest representation that reads back to the same double.
  char buffer[64];
  auto [ptr, ec] = std::to_chars(buffer, buffer + sizeof buffer, x);
  (void)ec;
  return std::string(buffer, ptr);
}

const Json* Json::find(std::string_view key) const
{
  if (!is_object()) return nullptr;
  for (const auto& [k, v] : object())
    if (k == key) return &v;
  return nullptr;
}

void Json::set(const std::string& key, Json value)
{
  auto& members = object();
  for (auto& [k, v] : members)
    if (k == key) {
      v = std::move(value);
      return;
    }
  members.emplace_back(key, std::move(value));
}

namespace {
void write_string(std::string& out, const std::string& s)
{
  out += '"';
  for (char c : s) {
    switch (c) {
    case '"':
      out += "\\\"";
      break;
    case '\\':
      out += "\\\\";
      break;
    case '\n':
      out += "\\n";
      break;
    case '\t':
      out += "\\t";
      break;
    case '\r':
      out += "\\r";
      break;
    default:
      if (static_cast<unsigned char>(c) < 0x20) {
        char buffer[8];
        std::snprintf(buffer, sizeof buffer, "\\u%04x", c);
        out += buffer;
      } else {
        out += c;
      }
    }
  }
  out += '"';
}
} // namespace

void Json::write(std::string& out, int indent, int depth) const
{
  const std::string pad =
      indent > 0 ? "\n" + std::string(static_cast<std::size_t>(indent * (depth + 1)), ' ') : "";
  const std::string end_pad =
      indent > 0 ? "\n" + std::string(static_cast<std::size_t>(indent * depth), ' ') : "";
  if (is_null()) {
    out += "null";
  } else if (auto* b = std::get_if<bool>(&value_)) {
    out += *b ? "true" : "false";
  } else if (auto* x = std::get_if<double>(&value_)) {
    out += json_number(*x);
  } else if (auto* s = std::get_if<std::string>(&value_)) {
    write_string(out, *s);
  } else if (auto* a = std::get_if<Array>(&value_)) {
    out += '[';
    for (std::size_t i = 0; i < a->size(); ++i) {
      out += i ? "," : "";
      out += pad;
      (*a)[i].write(out, indent, depth + 1);
    }
    out += a->empty() ? "]" : end_pad + "]";
  } else {
    const auto& o = std::get<Object>(value_);
    out += '{';
    for (std::size_t i = 0; i < o.size(); ++i) {
      out += i ? "," : "";
      out += pad;
      write_string(out, o[i].first);
      out += indent > 0 ? ": " : ":";
      o[i].second.write(out, indent, depth + 1);
    }
    out += o.empty() ? "}" : end_pad + "}";
  }
}

std::string Json::dump(int indent) const
{
  std::string out;
  write(out, indent, 0);
  return out;
}

namespace {
struct Parser {
  std::string_view text;
  std::size_t pos = 0;

  [[noreturn]] void fail(const std::string& what) const
  {
    throw std::runtime_error("JSON: " + what + " at offset " + std::to_string(pos));
  }
  void skip()
  {
    while (pos < text.size() &&
           (text[pos] == ' ' || text[pos] == '\n' || text[pos] == '\t' || text[pos] == '\r'))
      ++pos;
  }
  bool literal(std::string_view word)
  {
    if (text.substr(pos, word.size()) != word) return false;
    pos += word.size();
    return true;
  }
  std::string string()
  {
    if (text[pos] != '"') fail("expected a string");
    ++pos;
    std::string out;
    while (pos < text.size() && text[pos] != '"') {
      char c = text[pos++];
      if (c == '\\') {
        if (pos >= text.size()) fail("bad escape");
        const char e = text[pos++];
        switch (e) {
        case 'n':
          out += '\n';
          break;
        case 't':
          out += '\t';
          break;
        case 'r':
          out += '\r';
          break;
        case 'b':
          out += '\b';
          break;
        case 'f':
          out += '\f';
          break;
        case 'u': {
          if (pos + 4 > text.size()) fail("bad \\u escape");
          unsigned code = 0;
          std::from_chars(text.data() + pos, text.data() + pos + 4, code, 16);
          pos += 4;
          if (code < 0x80) {
            out += static_cast<char>(code);
          } else if (code < 0x800) {
            out += static_cast<char>(0xC0 | (code >> 6));
            out += static_cast<char>(0x80 | (code & 0x3F));
          } else {
            out += static_cast<char>(0xE0 | (code >> 12));
            out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
            out += static_cast<char>(0x80 | (code & 0x3F));
          }
          break;
        }
        default:
          out += e;
        }
      } else {
        out += c;
      }
    }
    if (pos >= text.size()) fail("unterminated string");
    ++pos;
    return out;
  }
  Json value()
  {
    skip();
    if (pos >= text.size()) fail("unexpected end");
    const char c = text[pos];
    if (c == '{') {
      ++pos;
      Json::Object members;
      skip();
      if (text[pos] == '}') {
        ++pos;
        return Json(std::move(members));
      }
      while (true) {
        skip();
        std::string key = string();
        skip();
        if (pos >= text.size() || text[pos] != ':') fail("expected ':'");
        ++pos;
        members.emplace_back(std::move(key), value());
        skip();
        if (pos < text.size() && text[pos] == ',') {
          ++pos;
          continue;
        }
        if (pos < text.size() && text[pos] == '}') {
          ++pos;
          return Json(std::move(members));
        }
        fail("expected ',' or '}'");
      }
    }
    if (c == '[') {
      ++pos;
      Json::Array items;
      skip();
      if (text[pos] == ']') {
        ++pos;
        return Json(std::move(items));
      }
      while (true) {
        items.push_back(value());
        skip();
        if (pos < text.size() && text[pos] == ',') {
          ++pos;
          continue;
        }
        if (pos < text.size() && text[pos] == ']') {
          ++pos;
          return Json(std::move(items));
        }
        fail("expected ',' or ']'");
      }
    }
    if (c == '"') return Json(string());
    if (literal("null")) return Json();
    if (literal("true")) return Json(true);
    if (literal("false")) return Json(false);
    double x = 0.0;
    auto [ptr, ec] = std::from_chars(text.data() + pos, text.data() + text.size(), x);
    if (ec != std::errc() || ptr == text.data() + pos) fail("unexpected character");
    pos = static_cast<std::size_t>(ptr - text.data());
    return Json(x);
  }
};
} // namespace

Json Json::parse(std::string_view text)
{
  Parser p{text};
  Json v = p.value();
  p.skip();
  if (p.pos != text.size()) p.fail("trailing characters");
  return v;
}

} // namespace ibvalve::hemodynamics
