// The logger: rank 0 alone prints; in a pipe progress is a plain line at most once per interval; the ETA
// counts this invocation's steps at this invocation's pace; every message also lands in the run's log file;
// warnings are kept, and errors under --strict.
#include <algorithm>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <mpi.h>

#include "base/errors.hpp"
#include "base/logger.hpp"
#include "io/files.hpp"

namespace ibvalve::base {
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
  log.begin_steps(0, 8);
  ::testing::internal::CaptureStdout();
  log.progress({1, 8, 0.1, 0.8, "fluid it 7, max|u| 2 cm/s, CFL 0.01"});
  log.progress({2, 8, 0.2, 0.8, ""});
  log.info("a message");
  const std::string out = ::testing::internal::GetCapturedStdout();
  if (rank == 0) {
    EXPECT_NE(out.find("step 1/8  t = 0.1 s / 0.8 s  "), std::string::npos) << out;
    EXPECT_NE(out.find(" s/step  ETA "), std::string::npos) << out;
    EXPECT_NE(out.find("  fluid it 7, max|u| 2 cm/s, CFL 0.01\n"), std::string::npos) << out;
    EXPECT_EQ(out.find("step 2"), std::string::npos) << "throttled: " << out;
    EXPECT_NE(out.find("a message\n"), std::string::npos);
  } else {
    EXPECT_EQ(out, "");
  }
}

// The ETA is this invocation's remaining steps at its own measured pace: a restart at step k of N has
// N - k steps to take, not the fraction of simulated time since t = 0 (which showed 18 min for 2.3 h
// left), and --stop-after-steps s ends it at k + s when that comes first.
TEST(Logger, EtaCountsTheStepsLeftInThisInvocation)
{
  // A fresh run of 100 steps, 10 taken in 5 s: 90 left at 0.5 s each.
  EXPECT_DOUBLE_EQ(eta_seconds(10, 0, 100, 5.0), 45.0);
  // Restarted at step 60 of 100: 10 steps in 5 s, 30 left, 15 s (not the 5 s x 0.3 / 0.7 of the old
  // fraction-of-time estimate, which counted the 60 earlier steps as taken in these 5 s).
  EXPECT_DOUBLE_EQ(eta_seconds(70, 60, 100, 5.0), 15.0);
  // Restarted at 60 of 100 with --stop-after-steps 20: the invocation ends at step 80.
  const long last = std::min(100L, 60L + 20L);
  EXPECT_DOUBLE_EQ(eta_seconds(70, 60, last, 5.0), 5.0);
  // A stop beyond the end: the end comes first.
  EXPECT_DOUBLE_EQ(eta_seconds(70, 60, std::min(100L, 60L + 500L), 5.0), 15.0);
  // Nothing measured yet: unknown, printed as --:--.
  EXPECT_LT(eta_seconds(60, 60, 100, 0.0), 0.0);
  EXPECT_EQ(format_duration(eta_seconds(60, 60, 100, 0.0)), "--:--");
  // At the last step nothing is left.
  EXPECT_DOUBLE_EQ(eta_seconds(80, 60, 80, 5.0), 0.0);
}

TEST(Logger, ProgressNamesTheStopOfThisInvocation)
{
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  Logger& log = Logger::global();
  log.set_progress_interval(1000.0);
  log.start_clock();
  log.begin_steps(60, 80); // restarted at step 60 of 100, --stop-after-steps 20
  ::testing::internal::CaptureStdout();
  log.progress({61, 100, 0.61, 1.0, ""});
  const std::string out = ::testing::internal::GetCapturedStdout();
  if (rank == 0) {
    EXPECT_NE(out.find("step 61/100  "), std::string::npos) << out;
    EXPECT_NE(out.find(" (stop at step 80)"), std::string::npos) << out;
  }
}

TEST(Logger, MessagesGoToTheLogFile)
{
  int rank = 0, pid = static_cast<int>(::getpid());
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Bcast(&pid, 1, MPI_INT, 0, MPI_COMM_WORLD);
  const auto path = std::filesystem::temp_directory_path() / (fmt::format("ibvalve_log_{}.txt", pid));
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
    const std::string text = io::read_text_file(path);
    EXPECT_NE(text.find("first line"), std::string::npos);
    EXPECT_NE(text.find("error: bad thing"), std::string::npos);
    std::filesystem::remove(path);
  }
}

// Warnings are kept once each on rank 0, handed to the run's record (run.json) as they come, and
// written into a log file opened after them (the case's warnings come before the run folder exists).
TEST(Logger, WarningsAreKeptRecordedAndLogged)
{
  int rank = 0, pid = static_cast<int>(::getpid());
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Bcast(&pid, 1, MPI_INT, 0, MPI_COMM_WORLD);
  Logger& log = Logger::global();
  log.clear_warnings();
  std::vector<std::vector<std::string>> recorded;
  ::testing::internal::CaptureStderr();
  log.warn("case.toml:3: fluid.density: 1060 g/mL is outside the typical 0.5 to 2 g/mL");
  log.set_warning_record([&](const std::vector<std::string>& all) { recorded.push_back(all); });
  log.warn("ib: dt = 1e-04 s is above the stability estimate 5e-05 s; the run may blow up");
  log.warn("ib: dt = 1e-04 s is above the stability estimate 5e-05 s; the run may blow up");
  log.set_warning_record([](const std::vector<std::string>&) { throw std::runtime_error("disk full"); });
  EXPECT_NO_THROW(log.warn("a third")); // a record that fails does not stop the run
  log.set_warning_record(nullptr);
  const auto path = std::filesystem::temp_directory_path() / (fmt::format("ibvalve_warnings_{}.txt", pid));
  log.open_file(path);
  log.close_file();
  ::testing::internal::GetCapturedStderr();
  if (rank == 0) {
    ASSERT_EQ(log.warnings().size(), 3u);
    EXPECT_EQ(log.warnings()[1],
              "ib: dt = 1e-04 s is above the stability estimate 5e-05 s; the run may blow up");
    ASSERT_EQ(recorded.size(), 1u); // the repeated warning is recorded once
    EXPECT_EQ(recorded[0].size(), 2u);
    const std::string text = io::read_text_file(path);
    EXPECT_NE(text.find("warning: case.toml:3: fluid.density: 1060 g/mL"), std::string::npos) << text;
    EXPECT_NE(text.find("warning: a third"), std::string::npos) << text;
    std::filesystem::remove(path);
  } else {
    EXPECT_TRUE(log.warnings().empty());
    EXPECT_TRUE(recorded.empty());
  }
  log.clear_warnings();
}

// Under --strict a warning is an error with the same one-line message, on every rank that gives it.
TEST(Logger, StrictMakesAWarningAnError)
{
  Logger& log = Logger::global();
  log.clear_warnings();
  log.set_strict(true);
  try {
    log.warn("PETSc options not used: -fluid_stokes_ksp_typo");
    ADD_FAILURE() << "no error under --strict";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "PETSc options not used: -fluid_stokes_ksp_typo");
  }
  log.set_strict(false);
  EXPECT_TRUE(log.warnings().empty());
}

TEST(Logger, AQuietTerminalStillLeavesTheRunsRecordInTheLogFile)
{
  int rank = 0, pid = static_cast<int>(::getpid());
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Bcast(&pid, 1, MPI_INT, 0, MPI_COMM_WORLD);
  const auto path = std::filesystem::temp_directory_path() / (fmt::format("ibvalve_quiet_log_{}.txt", pid));
  Logger& log = Logger::global();
  log.open_file(path);
  log.set_level(LogLevel::quiet);
  ::testing::internal::CaptureStdout();
  log.info("ib: dt = 5e-05 s is within the coupled stability estimate");
  log.verbose("a verbose detail");
  const std::string out = ::testing::internal::GetCapturedStdout();
  log.set_level(LogLevel::normal);
  log.close_file();
  if (rank == 0) {
    EXPECT_EQ(out, "");
    const std::string text = io::read_text_file(path);
    EXPECT_NE(text.find("within the coupled stability estimate"), std::string::npos) << text;
    EXPECT_EQ(text.find("a verbose detail"), std::string::npos) << text;
    std::filesystem::remove(path);
  }
}

} // namespace
} // namespace ibvalve::base
