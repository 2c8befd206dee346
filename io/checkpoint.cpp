#include "io/checkpoint.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "io/errors.hpp"

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

} // namespace

void add_checkpoint_schema(Schema& schema, const std::string& prefix)
{
  schema
      .add_integer(prefix + ".every",
                   "write a checkpoint every this many steps (0 = only when stopped early)")
      .defaults(std::int64_t{0})
      .at_least(0);
  schema.add_integer(prefix + ".keep", "newest checkpoints kept (older ones are deleted)")
      .defaults(std::int64_t{2})
      .at_least(1);
}

CheckpointSettings checkpoint_settings_from_config(const Config& config, const std::string& prefix)
{
  return CheckpointSettings{config.integer(prefix + ".every"), config.integer(prefix + ".keep")};
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
  const std::filesystem::path temporary = final_path.string() + ".partial";
  if (rank_ == 0) std::filesystem::create_directories(directory_);
  MPI_Barrier(comm_);
  {
    Hdf5File file(comm_, temporary, Hdf5File::Mode::create);
    save(file);
    // The header last: a file without it was not finished.
    file.write_attribute("step", static_cast<double>(header.step));
    file.write_attribute("time", header.time);
    file.write_attribute("timeseries_rows", static_cast<double>(header.timeseries_rows));
    file.write_attribute("complete", 1.0);
  }
  MPI_Barrier(comm_);
  if (rank_ == 0) {
    std::filesystem::rename(temporary, final_path);
    const auto files = list_newest_first(MPI_COMM_SELF, directory_);
    for (std::size_t i = static_cast<std::size_t>(settings_.keep); i < files.size(); ++i)
      std::filesystem::remove(files[i]);
  }
  MPI_Barrier(comm_);
  return final_path;
}

std::optional<std::filesystem::path> Checkpoints::latest() const
{
  for (const auto& file : list_newest_first(comm_, directory_)) {
    int good = 0;
    try {
      Hdf5File h5(comm_, file, Hdf5File::Mode::read);
      good = h5.read_attribute("complete") == 1.0 ? 1 : 0;
    } catch (const std::exception&) {
      good = 0; // torn or foreign file: try the one before
    }
    int all_good = 0;
    MPI_Allreduce(&good, &all_good, 1, MPI_INT, MPI_MIN, comm_);
    if (all_good) return file;
  }
  return std::nullopt;
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
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": cannot be read (the run to restart has no time series)");
  std::string kept, line;
  std::int64_t data_rows = -1; // the header is not a data row
  while (data_rows < rows && std::getline(in, line)) {
    kept += line + '\n';
    if (!line.empty() && line[0] != '#') ++data_rows;
  }
  if (data_rows < rows)
    throw InputError(path.string() + ": has " + std::to_string(std::max<std::int64_t>(data_rows, 0)) +
                     " rows but the checkpoint expects " + std::to_string(rows));
  in.close();
  const std::filesystem::path temporary = path.string() + ".truncating";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out << kept;
    if (!out) throw std::runtime_error("cannot write " + temporary.string());
  }
  std::filesystem::rename(temporary, path);
}

} // namespace ibvalve::io
