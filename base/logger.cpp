#include "base/logger.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include <fcntl.h>
#include <unistd.h>

#include <fmt/format.h>

#include "base/errors.hpp"

namespace ibvalve::base {

namespace {

/// Whether file descriptor `fd` of this process's parent is a terminal (read through /proc).
bool parent_descriptor_is_terminal(int fd)
{
  const std::string path = fmt::format("/proc/{}/fd/{}", getppid(), fd);
  const int opened = open(path.c_str(), O_RDONLY | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (opened < 0) return false;
  const bool terminal = isatty(opened) != 0;
  close(opened);
  return terminal;
}

/// The stream a progress line can be redrawn on, or null when the output does not reach a terminal.
std::FILE* progress_terminal()
{
  if (std::getenv("OMPI_COMM_WORLD_SIZE") == nullptr) return isatty(fileno(stderr)) ? stderr : nullptr;
  // Open MPI's mpiexec gives every rank a pseudo-terminal as stdout (a file or pipe behind mpiexec
  // included) and a pipe as stderr, and forwards both, carriage returns and unfinished lines as they
  // come. So the rank's own isatty says nothing: ask mpiexec's stdout, the rank's parent on the node
  // it was started from (a remote rank's parent is Open MPI's daemon, whose stdout is no terminal),
  // and draw on stdout, the channel the other messages take, so that the two stay in order. Tagged or
  // time-stamped output prefixes every piece forwarded and a redrawn line would be garbled.
  for (const char* prefixing :
       {"OMPI_MCA_orte_tag_output", "OMPI_MCA_orte_timestamp_output", "OMPI_MCA_orte_output_filename"})
    if (const char* value = std::getenv(prefixing); value != nullptr && *value != '\0' && *value != '0')
      return nullptr;
  return parent_descriptor_is_terminal(1) ? stdout : nullptr;
}

} // namespace

Logger& Logger::global()
{
  static Logger logger;
  return logger;
}

Logger::Logger() : draw_(progress_terminal()), start_(std::chrono::steady_clock::now())
{
  set_communicator(MPI_COMM_WORLD);
}

void Logger::set_communicator(MPI_Comm comm)
{
  int initialized = 0;
  MPI_Initialized(&initialized);
  int rank = 0;
  if (initialized) MPI_Comm_rank(comm, &rank);
  root_ = rank == 0;
}

void Logger::open_file(const std::filesystem::path& path)
{
  close_file();
  if (root_) file_ = std::fopen(path.c_str(), "a");
  // The warnings given before (the case's) belong to the run's record too.
  for (const std::string& warning : warnings_) write(stderr, "warning: ", warning, false);
}

void Logger::close_file()
{
  if (file_) std::fclose(file_);
  file_ = nullptr;
}

void Logger::write(std::FILE* stream, std::string_view prefix, std::string_view message, bool to_terminal)
{
  if (!root_) return;
  if (to_terminal) {
    finish_progress();
    std::fprintf(stream, "%.*s%.*s\n", static_cast<int>(prefix.size()), prefix.data(),
                 static_cast<int>(message.size()), message.data());
    std::fflush(stream);
  }
  if (file_) {
    std::fprintf(file_, "[%9.2f s] %.*s%.*s\n", wall_seconds(), static_cast<int>(prefix.size()),
                 prefix.data(), static_cast<int>(message.size()), message.data());
    std::fflush(file_);
  }
}

void Logger::info(std::string_view message)
{
  write(stdout, "", message, level_ >= LogLevel::normal);
}

void Logger::verbose(std::string_view message)
{
  if (level_ >= LogLevel::verbose) write(stdout, "", message);
}

void Logger::always(std::string_view message)
{
  write(stdout, "", message);
}

void Logger::warn(std::string_view message)
{
  if (strict_) throw InputError(std::string(message));
  write(stderr, "warning: ", message);
  if (!root_ || std::find(warnings_.begin(), warnings_.end(), message) != warnings_.end()) return;
  warnings_.emplace_back(message);
  if (!warning_record_) return;
  try {
    warning_record_(warnings_);
  } catch (const std::exception&) {
    // The record is a copy (a full disk must not stop the run): log.txt has the warning.
  }
}

void Logger::error(std::string_view message)
{
  write(stderr, "error: ", message);
}

void Logger::start_clock()
{
  start_ = std::chrono::steady_clock::now();
  last_progress_wall_ = -1.0;
}

double Logger::wall_seconds() const
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

std::string format_duration(double seconds)
{
  if (!std::isfinite(seconds) || seconds < 0) return "--:--";
  const long total = std::lround(seconds);
  const long h = total / 3600, m = (total / 60) % 60, s = total % 60;
  return h > 0 ? fmt::format("{}:{:02}:{:02}", h, m, s) : fmt::format("{}:{:02}", m, s);
}

void Logger::begin_steps(long first_step, long last_step)
{
  first_step_ = interval_step_ = first_step;
  last_step_ = last_step;
  interval_wall_ = wall_seconds();
  eta_.begin(first_step, interval_wall_);
  step_seconds_ = -1.0;
}

void Logger::progress(const Progress& p)
{
  if (!root_ || level_ < LogLevel::normal) return;
  const double wall = wall_seconds();
  // The time a step averaged over the current interval (the last one's once it is a step old).
  if (p.step > interval_step_)
    step_seconds_ = (wall - interval_wall_) / static_cast<double>(p.step - interval_step_);
  if (wall - interval_wall_ >= progress_interval_) {
    interval_step_ = p.step;
    interval_wall_ = wall;
  }
  const long last = last_step_ > first_step_ ? last_step_ : p.steps;
  eta_.record(p.step, wall);
  const double eta = eta_.seconds_left(last);
  const double done = p.steps > 0 ? 100.0 * static_cast<double>(p.step) / static_cast<double>(p.steps) : 0.0;
  std::ostringstream line;
  line.precision(4);
  line << "step " << p.step << "/" << p.steps << "  t = " << p.time << " s / " << p.end_time << " s ("
       << fmt::format("{:.1f}", done) << " %)  ";
  if (step_seconds_ >= 0)
    line << step_seconds_ << " s/step";
  else
    line << "-- s/step";
  line << "  ETA " << format_duration(eta);
  if (last < p.steps) line << " (stop at step " << last << ")";
  if (!p.details.empty()) line << "  " << p.details;
  const std::string text = line.str();
  if (draw_) {
    std::fprintf(draw_, "\r\033[K%s", text.c_str());
    std::fflush(draw_);
    progress_drawn_ = true;
  } else if (last_progress_wall_ < 0 || wall - last_progress_wall_ >= progress_interval_) {
    last_progress_wall_ = wall;
    write(stdout, "", text);
  }
}

void Logger::finish_progress()
{
  if (progress_drawn_) {
    std::fputc('\n', draw_);
    std::fflush(draw_);
    progress_drawn_ = false;
  }
}

} // namespace ibvalve::base
