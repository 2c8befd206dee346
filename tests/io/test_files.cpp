// Files a run writes are never half-written; CSV time series are read back with clear errors.
#include <filesystem>
#include <fmt/format.h>
#include <fstream>

#include <sys/stat.h>

#include <gtest/gtest.h>

#include "base/errors.hpp"
#include "io/files.hpp"

namespace ibvalve::io {
namespace {

std::filesystem::path temp(const std::string& name)
{
  return std::filesystem::temp_directory_path() / (fmt::format("ibvalve_files_{}_{}", ::getpid(), name));
}

TEST(Files, AtomicWriteReplacesTheWholeFileAndLeavesNoTemporary)
{
  const auto path = temp("atomic.txt");
  write_file_atomically(path, "first version, longer\n");
  write_file_atomically(path, "second\n");
  EXPECT_EQ(read_text_file(path), "second\n");
  for (const auto& entry : std::filesystem::directory_iterator(path.parent_path()))
    EXPECT_EQ(entry.path().string().find(path.string() + ".tmp"), std::string::npos);
  std::filesystem::remove(path);
}

TEST(Files, CsvRoundTripAndAppend)
{
  const auto path = temp("series.csv");
  {
    CsvWriter w(path, {"t", "Q"});
    w.write_row({0.0, 1.5});
  }
  {
    CsvWriter w(path, {"t", "Q"}, /*append=*/true);
    w.write_row({0.1, -2.25});
  }
  const CsvTable table = read_csv(path);
  EXPECT_EQ(table.columns, (std::vector<std::string>{"t", "Q"}));
  EXPECT_EQ(table.values("Q"), (std::vector<double>{1.5, -2.25}));
  EXPECT_THROW(table.column("P"), InputError);
  std::filesystem::remove(path);
}

TEST(Files, CsvUnitsLineFollowsTheHeaderOnceAndReadersSkipIt)
{
  // A new series: header, then "# units: ..."; a restart appends rows only. An older series without
  // the line (a run folder from before) is appended to as it is.
  const auto path = temp("units.csv"), old = temp("old.csv");
  {
    CsvWriter w(path, {"t", "Q"}, false, {"s", "mL/s"});
    w.write_row({0.0, 1.5});
  }
  {
    CsvWriter w(path, {"t", "Q"}, /*append=*/true, {"s", "mL/s"});
    w.write_row({0.1, -2.25});
  }
  EXPECT_EQ(read_text_file(path), "t,Q\n# units: s,mL/s\n0,1.5\n0.1,-2.25\n");
  const CsvTable table = read_csv(path);
  EXPECT_EQ(table.columns, (std::vector<std::string>{"t", "Q"}));
  EXPECT_EQ(table.values("Q"), (std::vector<double>{1.5, -2.25}));
  std::ofstream(old) << "t,Q\n0,1.5\n";
  {
    CsvWriter w(old, {"t", "Q"}, /*append=*/true, {"s", "mL/s"});
    w.write_row({0.1, -2.25});
  }
  EXPECT_EQ(read_text_file(old), "t,Q\n0,1.5\n0.1,-2.25\n");
  EXPECT_THROW(CsvWriter(temp("wrong.csv"), {"t", "Q"}, false, {"s"}), std::logic_error);
  for (const auto& p : {path, old, temp("wrong.csv")}) std::filesystem::remove(p);
}

TEST(Files, MalformedCsvLineIsNamed)
{
  const auto path = temp("bad.csv");
  std::ofstream(path) << "# comment\nt,P\n0,1\n0.1,abc\n";
  try {
    read_csv(path);
    FAIL() << "no error";
  } catch (const InputError& error) {
    // Names the place and what was expected, not the text found there (the file may be any file).
    EXPECT_EQ(std::string(error.what()),
              path.string() +
                  ":4: expected a number in column 2 of 2 (a CSV table of numbers under a header row)");
  }
  std::filesystem::remove(path);
}

TEST(Files, AFullDiskIsARunErrorNamingTheFileAndTheReason)
{
  // /dev/full answers every write with ENOSPC, as a full disk does.
  try {
    CsvWriter w("/dev/full", {"t", "Q"});
    FAIL() << "no error";
  } catch (const RunError& error) {
    EXPECT_EQ(std::string(error.what()), "/dev/full: cannot write: No space left on device");
  }
  try {
    write_file_atomically("/nonexistent_folder/config.toml", "x");
    FAIL() << "no error";
  } catch (const RunError& error) {
    EXPECT_EQ(std::string(error.what()),
              "/nonexistent_folder/config.toml: cannot write: No such file or directory");
  }
}

TEST(Files, ATornLastRowIsNamedAsTorn)
{
  const auto path = temp("torn.csv");
  std::ofstream(path) << "t,P,Q\n0,1,2\n0.1,1.5";
  try {
    read_csv(path);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(path.string() + ":3: the last row is torn"), std::string::npos)
        << error.what();
  }
  std::filesystem::remove(path);
}

TEST(Files, ACsvColumnNamedTwiceIsRefusedNamingFileLineAndColumn)
{
  // A reader by name would take one of the two silently (the first Q_valve, and the report's V_F of it).
  const auto path = temp("twice.csv");
  std::ofstream(path) << "# a comment\nt,Q_valve,Q_valve\n0,1,2\n";
  try {
    read_csv(path);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what())
                  .find(path.string() + ":2: column 'Q_valve' is named twice (columns 2 and 3)"),
              std::string::npos)
        << error.what();
  }
  std::filesystem::remove(path);
}

TEST(Files, InputFilesAreRegularFilesOfBoundedSize)
{
  // A device or a pipe could be read without end or block: refused without being opened.
  for (const char* device : {"/dev/null", "/dev/zero"}) {
    EXPECT_THROW(read_text_file(device), InputError) << device;
    EXPECT_THROW(read_csv(device), InputError) << device;
  }
  const auto fifo = temp("fifo.csv");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  try {
    read_csv(fifo);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()),
              fifo.string() + ": not a regular file (a pipe, a device or a socket); give a file");
  }
  std::filesystem::remove(fifo);
  // A file beyond its limit (sparse: no disk used) is refused before it is read.
  const auto big = temp("big.csv");
  std::ofstream(big) << "t,p\n0,1\n";
  std::filesystem::resize_file(big, (std::uintmax_t{3} << 20) + 1);
  EXPECT_THROW(read_csv(big, true, std::uintmax_t{3} << 20), InputError);
  try {
    read_text_file(big, std::uintmax_t{3} << 20);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()),
              big.string() + ": 3145729 bytes is more than the 3 MiB this file is read up to");
  }
  std::filesystem::remove(big);
}

TEST(Files, ANameIsNotAPath)
{
  EXPECT_EQ(folder_name_problem("W1FD1"), "");
  EXPECT_EQ(folder_name_problem("time step 1"), "");
  for (const char* path : {"", ".", "..", "../x", "a/b", "a\\b", "x\n"})
    EXPECT_NE(folder_name_problem(path), "") << path;
}

TEST(Files, AnOutputFolderThatCannotBeMadeIsBadInput)
{
  for (const char* folder : {"/proc/ibvalve/out", "/dev/null/out"}) {
    try {
      create_output_folder(folder);
      FAIL() << "no error for " << folder;
    } catch (const InputError& error) {
      EXPECT_EQ(
          std::string(error.what()).rfind(std::string(folder) + ": cannot create the output folder (", 0), 0u)
          << error.what();
    }
  }
}

} // namespace
} // namespace ibvalve::io
