// The logger: rank 0 alone prints; in a pipe progress is a plain line at most once per interval; the ETA
// counts this invocation's steps at the pace of its recent ones; every message also lands in the run's
// log file; warnings are kept, and errors under --strict.
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
#include "base/eta.hpp"
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
    EXPECT_NE(out.find("step 1/8  t = 0.1 s / 0.8 s (12.5 %)  "), std::string::npos) << out;
    EXPECT_NE(out.find(" s/step  ETA "), std::string::npos) << out;
    EXPECT_NE(out.find("  fluid it 7, max|u| 2 cm/s, CFL 0.01\n"), std::string::npos) << out;
    EXPECT_EQ(out.find("step 2"), std::string::npos) << "throttled: " << out;
    EXPECT_NE(out.find("a message\n"), std::string::npos);
  } else {
    EXPECT_EQ(out, "");
  }
}

// The ETA is this invocation's remaining steps at the pace of its recent steps (base/eta.hpp): a restart
// at step k of N has N - k steps to take, and --stop-after-steps s ends it at k + s when that comes first.
TEST(Eta, CountsTheStepsLeftInThisInvocation)
{
  // A fresh run of 100 steps, 10 taken in 5 s: 90 left at 0.5 s each.
  EtaEstimator fresh;
  fresh.begin(0, 0.0);
  fresh.record(10, 5.0);
  EXPECT_DOUBLE_EQ(fresh.seconds_left(100), 45.0);
  // Restarted at step 60 of 100: 10 steps in 5 s, 30 left, 15 s; with --stop-after-steps 20 it ends at 80.
  EtaEstimator restarted;
  restarted.begin(60, 0.0);
  EXPECT_LT(restarted.seconds_left(100), 0.0); // nothing measured yet: unknown, printed as --:--
  EXPECT_EQ(format_duration(restarted.seconds_left(100)), "--:--");
  restarted.record(70, 5.0);
  EXPECT_DOUBLE_EQ(restarted.seconds_left(100), 15.0);
  EXPECT_DOUBLE_EQ(restarted.seconds_left(std::min(100L, 60L + 20L)), 5.0);
  // At the last step nothing is left.
  restarted.record(80, 10.0);
  EXPECT_DOUBLE_EQ(restarted.seconds_left(80), 0.0);
}

// The first step's set-up is no step's pace: a first step of 100 s and 1 s a step after it give 1 s a
// step once the second step is measured (at step 4 the mean since the start, 25.75 s a step, said 41:12
// for the 96 steps left, against 1:36).
TEST(Eta, LeavesTheFirstStepsSetUpOut)
{
  EtaEstimator eta(300.0);
  eta.begin(0, 0.0);
  eta.record(1, 100.0);
  EXPECT_DOUBLE_EQ(eta.step_seconds(), 100.0); // the only step measured
  eta.record(2, 101.0);
  EXPECT_DOUBLE_EQ(eta.step_seconds(), 1.0);
  eta.record(4, 103.0);
  EXPECT_DOUBLE_EQ(eta.seconds_left(100), 96.0);
}

// A pace that changes (a loaded machine, a costlier phase of the cycle) is followed within the window:
// 1000 steps at 1 s, then steps at 2 s. The mean since the start lags (at step 1400: 1.29 s a step,
// 35 % short); the window's pace is 2 s once the window holds only the slower steps.
TEST(Eta, FollowsTheRecentPaceWithinItsWindow)
{
  EtaEstimator eta(300.0);
  eta.begin(0, 0.0);
  double wall = 0.0;
  for (long n = 1; n <= 1400; ++n) {
    wall += n <= 1000 ? 1.0 : 2.0;
    eta.record(n, wall);
  }
  EXPECT_NEAR(wall / 1400.0, 1.2857, 1e-4); // the mean since the start
  EXPECT_DOUBLE_EQ(eta.step_seconds(), 2.0);
  EXPECT_DOUBLE_EQ(eta.seconds_left(2000), 1200.0);
  // Within the window's first 300 s after the change the pace mixes the two: at most the window's share.
  EtaEstimator mixed(300.0);
  mixed.begin(0, 0.0);
  wall = 0.0;
  for (long n = 1; n <= 1050; ++n) {
    wall += n <= 1000 ? 1.0 : 2.0;
    mixed.record(n, wall);
  }
  EXPECT_GT(mixed.step_seconds(), 1.0);
  EXPECT_LT(mixed.step_seconds(), 2.0);
  // Strided records (the lumped model's every 1000 steps) measure the same pace.
  EtaEstimator strided(300.0);
  strided.begin(0, 0.0);
  for (long n = 1000; n <= 10000; n += 1000) strided.record(n, 0.01 * static_cast<double>(n));
  EXPECT_DOUBLE_EQ(strided.step_seconds(), 0.01);
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
