#pragma once
// Text helpers the schema, the validation and the writing of a case share (io/schema.cpp, io/config.cpp,
// io/config_writing.cpp): not part of io's interface.
#include <string>
#include <string_view>
#include <vector>

#include "io/config.hpp"

namespace ibvalve::io::detail {

/// "a number", "a list of strings", ...: what a key of `kind` holds, for messages and tables.
std::string kind_name(ValueKind kind);
/// The shortest text that reads back as `x` (no ".0" added: for messages and tables).
std::string format_number(double x);
/// "prefix.key", or `key` without a prefix.
std::string join_key(std::string_view prefix, std::string_view key);
/// "[0, 1] cm", "> 0 s", ...: a key's allowed range ("" for none).
std::string range_text(const KeySpec& s);
std::string join(const std::vector<std::string>& items, std::string_view separator);
/// "1 to 20 cP" for a key with a typical range ("" otherwise).
std::string typical_text(const KeySpec& s);

} // namespace ibvalve::io::detail
