#pragma once
// The one logger every rank-0 message goes through.
//
// Only rank 0 of the run's communicator writes. On a terminal, progress is a single line redrawn in
// place (step/total, simulated time and the share of the run done, wall time a step, ETA over a recent
// window, the model's solver figures); in a pipe or file it becomes a plain log line every
// `progress_interval` wall seconds, so CI logs stay readable. Under Open MPI's mpiexec a rank's own stdout is
// always a pseudo-terminal and its stderr a pipe, whatever mpiexec's output is, so there the terminal test
// asks mpiexec's stdout (docs/runs.md, "Progress and diagnostics"). Everything is also appended to the run
// folder's log.txt once a run has one. Warnings are kept (run.json and the report show them); under --strict
// a warning is an error.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include <mpi.h>

#include "base/eta.hpp"

namespace ibvalve::base {

enum class LogLevel { quiet = 0, normal = 1, verbose = 2 };

struct Progress {
  long step = 0;         // the step just taken
  long steps = 0;        // the run's last step
  double time = 0.0;     // simulated time, s
  double end_time = 0.0; // simulated end time, s
  std::string details;   // the model's figures of the step (solver iterations, max |u|, CFL); may be empty
};

class Logger {
 public:
  /// The process's logger.
  static Logger& global();

  /// Rank 0 of `comm` writes; the default is MPI_COMM_WORLD (or the only process before MPI starts).
  void set_communicator(MPI_Comm comm);
  /// The terminal's level. The log file keeps every message of the normal level (and verbose ones when
  /// the level is verbose) whatever the terminal shows: a run started with -q still leaves its record.
  void set_level(LogLevel level) { level_ = level; }
  LogLevel level() const { return level_; }
  /// Seconds between plain progress lines when stderr is not a terminal.
  void set_progress_interval(double seconds) { progress_interval_ = seconds; }
  bool is_root() const { return root_; }

  /// Appends every later message to `path` (rank 0 only), after the warnings kept so far. Closes any
  /// earlier file.
  void open_file(const std::filesystem::path& path);
  void close_file();

  void info(std::string_view message);
  void verbose(std::string_view message);
  /// "warning: ..." on stderr and in the log file, kept (warnings()); under set_strict an InputError
  /// with the message instead (exit 2).
  void warn(std::string_view message);
  /// One line on stdout (and in the log file), whatever the level: how a stopped run goes on.
  void always(std::string_view message);
  /// One line on stderr (and in the log file), whatever the level.
  void error(std::string_view message);

  /// Warnings turn into errors: warn() throws InputError (ibvalve run --strict).
  void set_strict(bool strict) { strict_ = strict; }
  bool strict() const { return strict_; }
  /// The warnings rank 0 has given since clear_warnings(), in order, each once (others keep none).
  const std::vector<std::string>& warnings() const { return warnings_; }
  void clear_warnings() { warnings_.clear(); }
  /// Called on rank 0 with every warning so far each time one is added (run.json keeps them); what it
  /// throws is dropped (log.txt holds the warning whatever happens). Empty: none.
  void set_warning_record(std::function<void(const std::vector<std::string>&)> record)
  {
    warning_record_ = std::move(record);
  }

  /// Restarts the wall clock of the run (log file stamps, "finished in").
  void start_clock();
  double wall_seconds() const;
  /// This invocation takes the steps after `first_step` up to `last_step`: the ETA (over a recent
  /// window, base/eta.hpp) and the time a step are measured from here.
  void begin_steps(long first_step, long last_step);
  void progress(const Progress& progress);
  /// Whether progress is redrawn in place (a terminal), else printed as plain lines.
  bool progress_in_place() const { return draw_ != nullptr; }
  /// Ends a progress line drawn in place, so the next message starts on a fresh line.
  void finish_progress();

 private:
  Logger();
  /// Writes on `stream` when `to_terminal`, and always to the log file.
  void write(std::FILE* stream, std::string_view prefix, std::string_view message, bool to_terminal = true);

  bool root_ = true;
  std::FILE* draw_ = nullptr; // the stream progress is redrawn on, when it reaches a terminal
  bool progress_drawn_ = false;
  LogLevel level_ = LogLevel::normal;
  double progress_interval_ = 10.0;
  double last_progress_wall_ = -1.0;
  long first_step_ = 0, last_step_ = 0; // this invocation's steps (begin_steps)
  EtaEstimator eta_;
  long interval_step_ = 0;     // the step and wall time the current
  double interval_wall_ = 0.0; // averaging interval of "s/step" began at
  double step_seconds_ = -1.0; // time a step over the last interval
  std::FILE* file_ = nullptr;
  bool strict_ = false;
  std::vector<std::string> warnings_;
  std::function<void(const std::vector<std::string>&)> warning_record_;
  std::chrono::steady_clock::time_point start_;
};

/// "1:02:03" or "4:05" for a duration in seconds.
std::string format_duration(double seconds);

} // namespace ibvalve::base
