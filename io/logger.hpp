#pragma once
// The one logger every rank-0 message goes through.
//
// Only rank 0 of the run's communicator writes. On a terminal, progress is a single line redrawn in
// place (step, simulated time, wall time, ETA); in a pipe or file it becomes a plain log line every
// `progress_interval` wall seconds, so CI logs stay readable. Everything is also appended to the
// run folder's log.txt once a run has one.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>

#include <mpi.h>

namespace ibvalve::io {

enum class LogLevel { quiet = 0, normal = 1, verbose = 2 };

struct Progress {
  long step = 0;
  double time = 0.0;     // simulated time, s
  double end_time = 0.0; // simulated end time, s
};

class Logger {
 public:
  /// The process's logger.
  static Logger& global();

  /// Rank 0 of `comm` writes; the default is MPI_COMM_WORLD (or the only process before MPI starts).
  void set_communicator(MPI_Comm comm);
  void set_level(LogLevel level) { level_ = level; }
  LogLevel level() const { return level_; }
  /// Seconds between plain progress lines when stderr is not a terminal.
  void set_progress_interval(double seconds) { progress_interval_ = seconds; }
  bool is_root() const { return root_; }

  /// Appends every later message to `path` (rank 0 only). Closes any earlier file.
  void open_file(const std::filesystem::path& path);
  void close_file();

  void info(std::string_view message);
  void verbose(std::string_view message);
  void warn(std::string_view message);
  /// One line on stdout (and in the log file), whatever the level: how a stopped run goes on.
  void always(std::string_view message);
  /// One line on stderr (and in the log file), whatever the level.
  void error(std::string_view message);

  /// Restarts the wall clock that progress and ETA are measured from.
  void start_clock();
  double wall_seconds() const;
  void progress(const Progress& progress);
  /// Ends a progress line drawn in place, so the next message starts on a fresh line.
  void finish_progress();

 private:
  Logger();
  void write(std::FILE* stream, std::string_view prefix, std::string_view message);

  bool root_ = true;
  bool tty_ = false;
  bool progress_drawn_ = false;
  LogLevel level_ = LogLevel::normal;
  double progress_interval_ = 10.0;
  double last_progress_wall_ = -1.0;
  std::FILE* file_ = nullptr;
  std::chrono::steady_clock::time_point start_;
};

/// "1:02:03" or "4:05" for a duration in seconds.
std::string format_duration(double seconds);

} // namespace ibvalve::io
