#include "io/logger.hpp"

#include <cmath>
#include <sstream>

#include <unistd.h>

namespace ibvalve::io {

Logger& Logger::global()
{
  static Logger logger;
  return logger;
}

Logger::Logger() : tty_(isatty(fileno(stderr)) != 0), start_(std::chrono::steady_clock::now())
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
}

void Logger::close_file()
{
  if (file_) std::fclose(file_);
  file_ = nullptr;
}

void Logger::write(std::FILE* stream, std::string_view prefix, std::string_view message)
{
  if (!root_) return;
  finish_progress();
  std::fprintf(stream, "%.*s%.*s\n", static_cast<int>(prefix.size()), prefix.data(),
               static_cast<int>(message.size()), message.data());
  std::fflush(stream);
  if (file_) {
    std::fprintf(file_, "[%9.2f s] %.*s%.*s\n", wall_seconds(), static_cast<int>(prefix.size()),
                 prefix.data(), static_cast<int>(message.size()), message.data());
    std::fflush(file_);
  }
}

void Logger::info(std::string_view message)
{
  if (level_ >= LogLevel::normal) write(stdout, "", message);
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
  write(stderr, "warning: ", message);
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
  char buffer[32];
  if (h > 0)
    std::snprintf(buffer, sizeof buffer, "%ld:%02ld:%02ld", h, m, s);
  else
    std::snprintf(buffer, sizeof buffer, "%ld:%02ld", m, s);
  return buffer;
}

void Logger::progress(const Progress& p)
{
  if (!root_ || level_ < LogLevel::normal) return;
  const double wall = wall_seconds();
  const double fraction = p.end_time > 0 ? p.time / p.end_time : 0.0;
  const double eta = fraction > 0 ? wall * (1.0 - fraction) / fraction : -1.0;
  char line[200];
  std::snprintf(line, sizeof line, "step %ld  t = %.6g s / %.6g s (%5.1f %%)  wall %s  ETA %s", p.step,
                p.time, p.end_time, 100.0 * fraction, format_duration(wall).c_str(),
                format_duration(eta).c_str());
  if (tty_) {
    std::fprintf(stderr, "\r\033[K%s", line);
    std::fflush(stderr);
    progress_drawn_ = true;
  } else if (last_progress_wall_ < 0 || wall - last_progress_wall_ >= progress_interval_) {
    last_progress_wall_ = wall;
    write(stdout, "", line);
  }
}

void Logger::finish_progress()
{
  if (progress_drawn_) {
    std::fputc('\n', stderr);
    std::fflush(stderr);
    progress_drawn_ = false;
  }
}

} // namespace ibvalve::io
