#pragma once
// The little JSON the reports need: a value tree, a writer and a strict reader (RFC 8259 subset:
// no duplicate-key handling, numbers as double). The project has no JSON library among its
// dependencies and metrics.json is small, so this is enough.
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace ibvalve::hemodynamics {

class Json {
 public:
  using Array = std::vector<Json>;
  using Object = std::vector<std::pair<std::string, Json>>; // keeps the insertion order

  Json() = default; // null
  Json(std::nullptr_t) {}
  Json(bool b) : value_(b) {}
  Json(double x) : value_(x) {}
  Json(int x) : value_(static_cast<double>(x)) {}
  Json(long x) : value_(static_cast<double>(x)) {}
  Json(const char* s) : value_(std::string(s)) {}
  Json(std::string s) : value_(std::move(s)) {}
  Json(Array a) : value_(std::move(a)) {}
  Json(Object o) : value_(std::move(o)) {}

  bool is_null() const { return std::holds_alternative<std::monostate>(value_); }
  bool is_number() const { return std::holds_alternative<double>(value_); }
  bool is_string() const { return std::holds_alternative<std::string>(value_); }
  bool is_object() const { return std::holds_alternative<Object>(value_); }
  bool is_array() const { return std::holds_alternative<Array>(value_); }
  double number() const { return std::get<double>(value_); }
  const std::string& string() const { return std::get<std::string>(value_); }
  const Array& array() const { return std::get<Array>(value_); }
  const Object& object() const { return std::get<Object>(value_); }
  Object& object() { return std::get<Object>(value_); }
  /// Member of an object, or nullptr.
  const Json* find(std::string_view key) const;
  /// Adds or replaces a member (this must be an object).
  void set(const std::string& key, Json value);

  /// Indented text; numbers with 17 significant digits (exact round trip); NaN/inf become null.
  std::string dump(int indent = 2) const;
  /// Parses text; std::runtime_error with the offset of the problem.
  static Json parse(std::string_view text);

 private:
  void write(std::string& out, int indent, int depth) const;
  std::variant<std::monostate, bool, double, std::string, Array, Object> value_;
};

/// A number as JSON writes it (17 significant digits, shortest form that reads back identically).
std::string json_number(double x);

} // namespace ibvalve::hemodynamics
