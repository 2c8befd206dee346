#pragma once
// Checkpoints of a run, so that `ibvalve run --restart RUN_DIR` continues it.
//
// A checkpoint is one HDF5 file <run>/checkpoints/step_<n>.h5 holding the model's state (datasets it
// writes itself), a header (step, time, rows of timeseries.csv so far), the case it is of
// (case_record) and a checksum of all of it. It is written under a
// temporary name and renamed into place once closed, so a run killed while writing leaves the previous
// checkpoint as the last good one. On restart the model reads the newest complete checkpoint, cuts
// timeseries.csv back to the rows it had then, and continues; with the same rank count the arithmetic
// is the same as an uninterrupted run's, so the series agree to the last bit.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include <mpi.h>

#include "io/config.hpp"
#include "io/hdf5.hpp"
#include "io/key_binder.hpp"

namespace ibvalve::io {

struct CheckpointSettings {
  std::int64_t every = 0; // steps between checkpoints; 0 = only when a run is stopped early
  std::int64_t keep = 2;  // newest checkpoints kept; older ones are deleted
  /// The case the checkpoints are of (case_record): recorded in each, compared on restart.
  std::string case_record;
};

/// Keys a restart may change (`--restart RUN_DIR --set ...`): how long the run goes on (time.end,
/// time.cycles), what and how often it writes (output.*, log.*, report.*, checkpoint.*), its name and
/// the PETSc options (solver monitors, tolerances). Every other key is part of the case a checkpoint
/// records.
inline constexpr const char* restart_may_change[] = {"name", "time.end", "time.cycles", "output.",
                                                     "log.", "report.",  "checkpoint.", "petsc.options"};

/// The case as a checkpoint records it: one `key = value` line per key of the resolved configuration
/// (every default written out), in key order, without the keys of restart_may_change. The keys the
/// case file leaves at their default are marked "  (default)" for the comparison and stored without
/// the mark. A restart refuses a checkpoint whose record differs in any value, except a key the
/// checkpoint does not record at all (its build did not have it) that is at its default here.
std::string case_record(const Config& config);

/// Declares or reads `<prefix>.every` and `<prefix>.keep` into `settings` (io/key_binder.hpp); its
/// case_record is the reader's to fill in, case_record(config), once every key is read.
void bind(KeyBinder& keys, CheckpointSettings& settings, const std::string& prefix = "checkpoint");

/// What every checkpoint records besides the model's own state.
struct CheckpointHeader {
  std::int64_t step = 0;            // steps completed
  double time = 0.0;                // simulated time reached, s
  std::int64_t timeseries_rows = 0; // data rows of timeseries.csv written so far
};

class Checkpoints {
 public:
  /// Every call is collective over `comm` (the ranks that hold the model's state).
  Checkpoints(MPI_Comm comm, std::filesystem::path run_directory, CheckpointSettings settings);

  /// Whether step `step` (steps completed) is one to checkpoint at.
  bool due(std::int64_t step) const { return settings_.every > 0 && step % settings_.every == 0; }
  /// Whether step `step` of a run of `steps` is one to checkpoint at: every `every` steps and the last
  /// step (so a finished run can be lengthened with --restart --set time.end=...).
  bool due(std::int64_t step, std::int64_t steps) const
  {
    return settings_.every > 0 && (step % settings_.every == 0 || step == steps);
  }

  /// Writes a checkpoint: `save` writes the model's datasets into the open file, then the header and the
  /// case record; rank 0 seals it with the checksum of its content and `complete`, renames it into
  /// place and deletes checkpoints beyond `keep`.
  std::filesystem::path write(const CheckpointHeader& header,
                              const std::function<void(Hdf5File&)>& save) const;

  /// The newest checkpoint that is complete and intact (its checksum matches its content), of this
  /// case; nullopt when there is none. A torn or corrupt one is passed over with a warning naming it;
  /// one of another case or model is an InputError naming the file and the first key that differs.
  std::optional<std::filesystem::path> latest() const;

  /// Opens a checkpoint, hands it to `restore`, and returns its header.
  CheckpointHeader read(const std::filesystem::path& file,
                        const std::function<void(const Hdf5File&)>& restore) const;

  const std::filesystem::path& directory() const { return directory_; }

 private:
  MPI_Comm comm_;
  int rank_ = 0;
  std::filesystem::path directory_;
  CheckpointSettings settings_;
};

/// Cuts a CSV time series back to its header line and its first `rows` data rows (on restart, the rows
/// written after the checkpoint are written again).
void truncate_csv_rows(const std::filesystem::path& path, std::int64_t rows);

} // namespace ibvalve::io
