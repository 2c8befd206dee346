#pragma once
// A run folder's config.toml (Config::resolved_toml) read back for people, as the report's inputs show
// it: each value in its shortest exact form with the unit its comment names.
#include <filesystem>
#include <string>
#include <vector>

namespace ibvalve::io {

struct RecordedEntry {
  std::string key;   ///< dotted, key[i].field in a table list
  std::string value; ///< numbers in their shortest exact form (fmt's "{}": 0.6, not 0.59999999999999998;
                     ///< 0, not -0.0), strings as TOML writes them, lists element by element
  std::string unit;  ///< the unit of the key's comment ("[mmHg] ..."), "" for none
};

/// Every value of `config_file` in file order; InputError naming the file when it cannot be read.
std::vector<RecordedEntry> read_recorded_config(const std::filesystem::path& config_file);

} // namespace ibvalve::io
