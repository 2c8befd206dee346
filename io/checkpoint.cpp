#include "io/checkpoint.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "base/errors.hpp"
#include "base/logger.hpp"
#include "io/collective.hpp"
#include "io/files.hpp"

namespace ibvalve::io {

namespace {

constexpr const char* prefix_name = "step_";
constexpr const char* suffix_name = ".h5";

std::string file_name(std::int64_t step)
{
  std::ostringstream os;
  os << prefix_name;
  os.width(9);
  os.fill('0');
  os << step << suffix_name;
  return os.str();
}

/// The step a checkpoint file name carries, or -1 for any other file.
std::int64_t step_of(const std::filesystem::path& file)
{
  const std::string name = file.filename().string();
  const std::string prefix = prefix_name, suffix = suffix_name;
  if (name.size() <= prefix.size() + suffix.size() || name.rfind(prefix, 0) != 0 ||
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
    return -1;
  const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
  if (!std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) return -1;
  return std::stoll(digits);
}

/// Checkpoint files in the folder, newest first (rank 0 lists; every rank gets the same list).
std::vector<std::filesystem::path> list_newest_first(MPI_Comm comm, const std::filesystem::path& directory)
{
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  std::string joined;
  if (rank == 0 && std::filesystem::is_directory(directory)) {
    std::vector<std::pair<std::int64_t, std::string>> found;
    for (const auto& entry : std::filesystem::directory_iterator(directory))
      if (const auto step = step_of(entry.path()); step >= 0) found.emplace_back(step, entry.path().string());
    std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    for (const auto& f : found) joined += f.second + '\n';
  }
  int length = static_cast<int>(joined.size());
  MPI_Bcast(&length, 1, MPI_INT, 0, comm);
  joined.resize(static_cast<std::size_t>(length));
  MPI_Bcast(joined.data(), length, MPI_CHAR, 0, comm);
  std::vector<std::filesystem::path> files;
  std::istringstream in(joined);
  for (std::string line; std::getline(in, line);) files.emplace_back(line);
  return files;
}

/// Root attributes the checksum does not cover: the checksum itself and the seal written after it.
const std::vector<std::string> unhashed_attributes{"checksum", "complete"};

std::string hex(std::uint64_t value)
{
  return fmt::format("{:016x}", value);
}

bool restart_may_change_key(const std::string& key)
{
  for (const std::string prefix : restart_may_change)
    if (prefix.back() == '.' ? key.rfind(prefix, 0) == 0 : key == prefix) return true;
  return false;
}

/// What case_record writes after the value of a key the case file leaves at its default.
constexpr std::string_view default_marker = "  (default)";

/// The record as a checkpoint stores it: the marks say how this run's case file reads, which a
/// restart (reading the run's resolved config.toml, every key written) would not repeat, and a
/// restarted run's checkpoints are the uninterrupted run's bit for bit.
std::string without_default_marks(const std::string& record)
{
  std::string out;
  std::istringstream in(record);
  for (std::string line; std::getline(in, line);) {
    if (line.ends_with(default_marker)) line.resize(line.size() - default_marker.size());
    out += line + '\n';
  }
  return out;
}

struct RecordedValue {
  std::string text;        // as TOML writes it
  bool at_default = false; // marked by case_record (the current case's; stored records have none)
};

std::map<std::string, RecordedValue> record_keys(const std::string& record)
{
  std::map<std::string, RecordedValue> keys;
  std::istringstream in(record);
  for (std::string line; std::getline(in, line);) {
    const auto equals = line.find(" = ");
    if (equals == std::string::npos) continue;
    RecordedValue value{line.substr(equals + 3), false};
    if (value.text.ends_with(default_marker)) {
      value.text.resize(value.text.size() - default_marker.size());
      value.at_default = true;
    }
    keys[line.substr(0, equals)] = value;
  }
  return keys;
}

/// Why a checkpoint of case `stored` does not continue case `current`: its model or its first key
/// that differs; empty when it is the same case.
std::string case_difference(const std::string& stored, const std::string& current)
{
  if (stored == current) return {};
  const auto a = record_keys(stored), b = record_keys(current);
  const auto model = [](const std::map<std::string, RecordedValue>& keys) {
    const auto found = keys.find("model");
    if (found == keys.end()) return std::string("(no)");
    std::string name = found->second.text; // a TOML string: 'fluid'
    if (name.size() >= 2 && (name.front() == '\'' || name.front() == '"'))
      name = name.substr(1, name.size() - 2);
    return name;
  };
  if (model(a) != model(b))
    return "a checkpoint of the " + model(a) + " model, not of this " + model(b) + " case";
  std::map<std::string, RecordedValue> all = a;
  all.insert(b.begin(), b.end());
  for (const auto& [key, ignored] : all) {
    const auto x = a.find(key), y = b.find(key);
    // A key the checkpoint's build did not have, left at its default here: a newer build continues an
    // older build's run as long as what it added keeps the behaviour it had.
    if (x == a.end() && y != b.end() && y->second.at_default) continue;
    const std::string there = x == a.end() ? std::string("not set") : x->second.text;
    const std::string here = y == b.end() ? std::string("not set") : y->second.text;
    if (there != here)
      return "not a checkpoint of this case: " + key + " is " + there + " there but " + here +
             " here (a restart may change only time.end, time.cycles, output.*, log.*, report.*, "
             "checkpoint.*, name and petsc.options)";
  }
  return {}; // the same values; the records differ only in their default marks
}

enum class Verdict { good, damaged, foreign };

/// Whether a checkpoint file continues the case `record` (rank 0 alone reads it).
std::pair<Verdict, std::string> inspect(const std::filesystem::path& file, const std::string& record)
{
  // A pipe or a device under a checkpoint's name would block the restart or never end.
  if (!std::filesystem::is_regular_file(file)) return {Verdict::damaged, "it is not a regular file"};
  try {
    Hdf5File h5(MPI_COMM_SELF, file, Hdf5File::Mode::read);
    if (!h5.has_attribute("complete") || h5.read_attribute("complete") != 1.0)
      return {Verdict::damaged, "it was not finished"};
    if (!h5.has_attribute("checksum") || !h5.has_attribute("case"))
      return {Verdict::damaged, "it has no checksum (written by an older ibvalve)"};
    if (h5.read_string_attribute("checksum") != hex(h5.content_hash(unhashed_attributes)))
      return {Verdict::damaged, "its content does not match its checksum"};
    if (const std::string why = case_difference(h5.read_string_attribute("case"), record); !why.empty())
      return {Verdict::foreign, why};
    return {Verdict::good, {}};
  } catch (const std::exception&) {
    return {Verdict::damaged, "it cannot be read as HDF5"};
  }
}

} // namespace

std::string case_record(const Config& config)
{
  const toml::table resolved = toml::parse(config.resolved_toml());
  std::vector<std::string> lines;
  for (const auto& [key, value] : io::flattened(resolved))
    if (!restart_may_change_key(key)) {
      // Config::where names the file alone for a key the case file (or --set) does not give.
      const bool at_default = config.where(key) == config.file().string();
      lines.push_back(key + " = " + value + (at_default ? std::string(default_marker) : std::string()));
    }
  std::sort(lines.begin(), lines.end());
  std::string record;
  for (const auto& line : lines) record += line + '\n';
  return record;
}

void bind(KeyBinder& keys, CheckpointSettings& settings, const std::string& prefix)
{
  keys.integer(prefix + ".every", "write a checkpoint every this many steps (0 = only when stopped early)",
               settings.every)
      .defaults(std::int64_t{0})
      .at_least(0);
  keys.integer(prefix + ".keep", "newest checkpoints kept (older ones are deleted)", settings.keep)
      .defaults(std::int64_t{2})
      .at_least(1);
}

Checkpoints::Checkpoints(MPI_Comm comm, std::filesystem::path run_directory, CheckpointSettings settings)
    : comm_(comm), directory_(std::move(run_directory) / "checkpoints"), settings_(settings)
{
  MPI_Comm_rank(comm_, &rank_);
}

std::filesystem::path Checkpoints::write(const CheckpointHeader& header,
                                         const std::function<void(Hdf5File&)>& save) const
{
  const std::filesystem::path final_path = directory_ / file_name(header.step);
  create_directories_on_root(comm_, directory_);
  {
    // Built in memory by rank 0 and written at close() beside its name, then renamed into place
    // (io/hdf5.hpp): a run that fails or is killed meanwhile leaves the previous checkpoint the newest.
    Hdf5File file(comm_, final_path, Hdf5File::Mode::create);
    save(file);
    file.write_attribute("step", static_cast<double>(header.step));
    file.write_attribute("time", header.time);
    file.write_attribute("timeseries_rows", static_cast<double>(header.timeseries_rows));
    file.write_string_attribute("case", without_default_marks(settings_.case_record));
    // The seal: the checksum of everything stored, then `complete` (a file without it was not
    // finished). Rank 0 hashes what it built; the other ranks' value is not used.
    file.write_string_attribute("checksum", hex(file.content_hash(unhashed_attributes)));
    file.write_attribute("complete", 1.0);
    file.close();
  }
  // Rank 0 prunes; a failure there reaches every rank.
  on_root(comm_, [&] {
    const auto files = list_newest_first(MPI_COMM_SELF, directory_);
    for (std::size_t i = static_cast<std::size_t>(settings_.keep); i < files.size(); ++i)
      std::filesystem::remove(files[i]);
  });
  return final_path;
}

std::optional<std::filesystem::path> Checkpoints::latest() const
{
  std::string chosen;
  on_root(comm_, [&] {
    for (const auto& file : list_newest_first(MPI_COMM_SELF, directory_)) {
      const auto [verdict, why] = inspect(file, settings_.case_record);
      if (verdict == Verdict::good) {
        chosen = file.string();
        return;
      }
      if (verdict == Verdict::foreign) throw InputError(file.string() + ": " + why);
      base::Logger::global().warn("skipping checkpoint " + file.string() + ": " + why +
                                  "; trying the one before");
    }
  });
  int length = static_cast<int>(chosen.size());
  MPI_Bcast(&length, 1, MPI_INT, 0, comm_);
  chosen.resize(static_cast<std::size_t>(length));
  MPI_Bcast(chosen.data(), length, MPI_CHAR, 0, comm_);
  if (chosen.empty()) return std::nullopt;
  return std::filesystem::path(chosen);
}

CheckpointHeader Checkpoints::read(const std::filesystem::path& file,
                                   const std::function<void(const Hdf5File&)>& restore) const
{
  Hdf5File h5(comm_, file, Hdf5File::Mode::read);
  CheckpointHeader header;
  header.step = static_cast<std::int64_t>(h5.read_attribute("step"));
  header.time = h5.read_attribute("time");
  header.timeseries_rows = static_cast<std::int64_t>(h5.read_attribute("timeseries_rows"));
  restore(h5);
  return header;
}

void truncate_csv_rows(const std::filesystem::path& path, std::int64_t rows)
{
  check_input_file(path, max_table_bytes);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": cannot be read (the run to restart has no time series)");
  std::string kept, line;
  std::int64_t data_rows = -1; // the header is not a data row
  while (data_rows < rows && std::getline(in, line)) {
    kept += line + '\n';
    if (!line.empty() && line[0] != '#') ++data_rows;
  }
  if (data_rows < rows)
    throw InputError(fmt::format("{}: has {} rows but the checkpoint expects {}", path.string(),
                                 std::max<std::int64_t>(data_rows, 0), rows));
  in.close();
  write_file_atomically(path, kept);
}

} // namespace ibvalve::io
