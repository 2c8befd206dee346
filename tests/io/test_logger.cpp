// The logger: rank 0 alone prints; in a pipe progress is a plain line at most once per interval; every
// message also lands in the run's log file.
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <mpi.h>

#include "io/files.hpp"
#include "io/logger.hpp"

namespace ibvalve::io {
namespace {

TEST(Logger, DurationsReadAsClockTimes)
{
  EXPECT_EQ(format_duration(0), "0:00");
  EXPECT_EQ(format_duration(65.4), "1:05");
  EXPECT_EQ(format_duration(3723), "1:02:03");
  EXPECT_EQ(format_duration(-1), "--:--");
}

TEST(Logger, ProgressInAPipeIsThrottledAndOnlyRankZeroPrints)
{
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  Logger& log = Logger::global();
  log.set_communicator(MPI_COMM_WORLD);
  log.set_progress_interval(1000.0);
  log.start_clock();
  ::testing::internal::CaptureStdout();
  log.progress({1, 0.1, 0.8});
  log.progress({2, 0.2, 0.8});
  log.info("a message");
  const std::string out = ::testing::internal::GetCapturedStdout();
  if (rank == 0) {
    EXPECT_NE(out.find("step 1  t = 0.1 s / 0.8 s ( 12.5 %)"), std::string::npos) << out;
    EXPECT_EQ(out.find("step 2"), std::string::npos) << "throttled: " << out;
    EXPECT_NE(out.find("a message\n"), std::string::npos);
  } else {
    EXPECT_EQ(out, "");
  }
}

TEST(Logger, MessagesGoToTheLogFile)
{
  int rank = 0, pid = static_cast<int>(::getpid());
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Bcast(&pid, 1, MPI_INT, 0, MPI_COMM_WORLD);
  const auto path = std::filesystem::temp_directory_path() / ("ibvalve_log_" + std::to_string(pid) + ".txt");
  Logger& log = Logger::global();
  log.open_file(path);
  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  log.info("first line");
  log.warn("careful");
  log.error("bad thing");
  ::testing::internal::GetCapturedStdout();
  const std::string err = ::testing::internal::GetCapturedStderr();
  log.close_file();
  if (rank == 0) {
    EXPECT_EQ(err, "warning: careful\nerror: bad thing\n");
    const std::string text = read_text_file(path);
    EXPECT_NE(text.find("first line"), std::string::npos);
    EXPECT_NE(text.find("error: bad thing"), std::string::npos);
    std::filesystem::remove(path);
  }
}

} // namespace
} // namespace ibvalve::io
