// Checkpoints (io/checkpoint.hpp): a distributed state written by every rank reads back bit for bit;
// the newest complete checkpoint is found and a torn file or an unfinished temporary is passed over;
// only the newest `keep` survive; a time series is cut back to the rows a checkpoint recorded; a
// checkpoint whose content no longer matches its checksum is passed over, one of another case refused,
// and one of an older build that lacked a key continues only while that key is at its default.
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <utility>

#include <gtest/gtest.h>
#include <mpi.h>
#include <unistd.h>

#include "base/errors.hpp"
#include "io/checkpoint.hpp"
#include "io/files.hpp"

namespace ibvalve::io {
namespace {

/// A fresh run folder every rank agrees on (rank 0's process id names it).
std::filesystem::path shared_run_directory(const std::string& name)
{
  int pid = static_cast<int>(::getpid());
  MPI_Bcast(&pid, 1, MPI_INT, 0, MPI_COMM_WORLD);
  const auto dir = std::filesystem::temp_directory_path() / (fmt::format("ibvalve_ckpt_{}_{}", name, pid));
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0) {
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  return dir;
}

/// This rank and the number of ranks of MPI_COMM_WORLD.
std::pair<int, int> world()
{
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return {rank, size};
}

/// Each rank's block of a global state: values that are not short binary fractions, so a lossy
/// round trip would show.
std::vector<double> block_of(int rank, std::size_t n, double seed)
{
  std::vector<double> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = std::sin(seed + 0.1 * static_cast<double>(rank * n + i)) / 3.0;
  return v;
}

void save_block(Hdf5File& h5, int rank, int size, const std::vector<double>& block)
{
  const std::vector<hsize_t> global{block.size() * static_cast<hsize_t>(size)};
  const std::vector<hsize_t> offset{block.size() * static_cast<hsize_t>(rank)}, count{block.size()};
  h5.write_block("state/u", block, global, offset, count);
}

TEST(Checkpoints, DistributedStateRoundTripsExactlyAndTheNewestGoodOneIsFound)
{
  const auto [rank, size] = world();
  const auto dir = shared_run_directory("roundtrip");
  const Checkpoints checkpoints(MPI_COMM_WORLD, dir, CheckpointSettings{10, 2, {}});
  EXPECT_FALSE(checkpoints.latest().has_value());
  EXPECT_TRUE(checkpoints.due(20));
  EXPECT_FALSE(checkpoints.due(25));

  const std::size_t n = 7;
  for (std::int64_t step : {10, 20, 30}) {
    const auto block = block_of(rank, n, static_cast<double>(step));
    const auto file = checkpoints.write({step, 1e-3 * static_cast<double>(step), step / 2},
                                        [&](Hdf5File& h5) { save_block(h5, rank, size, block); });
    EXPECT_EQ(file.filename().string(), fmt::format("step_0000000{}.h5", step));
  }
  // keep = 2: step 10 is gone.
  EXPECT_FALSE(std::filesystem::exists(dir / "checkpoints" / "step_000000010.h5"));
  EXPECT_TRUE(std::filesystem::exists(dir / "checkpoints" / "step_000000020.h5"));

  // A newer file torn by a crash, and a temporary never renamed, are passed over.
  if (rank == 0) {
    std::ofstream(dir / "checkpoints" / "step_000000040.h5") << "torn";
    std::ofstream(dir / "checkpoints" / "step_000000050.h5.partial") << "unfinished";
  }
  MPI_Barrier(MPI_COMM_WORLD);
  const auto latest = checkpoints.latest();
  ASSERT_TRUE(latest.has_value());
  EXPECT_EQ(latest->filename().string(), "step_000000030.h5");

  std::vector<double> restored;
  const CheckpointHeader header = checkpoints.read(*latest, [&](const Hdf5File& h5) {
    const std::vector<hsize_t> offset{n * static_cast<hsize_t>(rank)}, count{n};
    restored = h5.read_block("state/u", offset, count);
  });
  EXPECT_EQ(header.step, 30);
  EXPECT_EQ(header.time, 1e-3 * 30.0);
  EXPECT_EQ(header.timeseries_rows, 15);
  EXPECT_EQ(restored, block_of(rank, n, 30.0)); // bit for bit
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank == 0) std::filesystem::remove_all(dir);
}

TEST(Checkpoints, AChangedValueIsPassedOverAndAnotherCaseIsRefused)
{
  const auto [rank, size] = world();
  const auto dir = shared_run_directory("validate");
  const std::string record = "model = 'lumped'\nvalve.max_area_fraction = 0.6\n";
  const Checkpoints checkpoints(MPI_COMM_WORLD, dir, CheckpointSettings{10, 3, record});
  const std::size_t n = 5;
  for (std::int64_t step : {10, 20}) {
    const auto block = block_of(rank, n, static_cast<double>(step));
    checkpoints.write({step, 1e-3 * static_cast<double>(step), step},
                      [&](Hdf5File& h5) { save_block(h5, rank, size, block); });
  }
  ASSERT_EQ(checkpoints.latest()->filename().string(), "step_000000020.h5");

  // One value of step 20's state changed behind the checkpoint's back (a flipped bit, a bad disk).
  if (rank == 0) {
    const auto file = dir / "checkpoints" / "step_000000020.h5";
    const hid_t h5 = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    const hid_t dataset = H5Dopen2(h5, "state/u", H5P_DEFAULT);
    std::vector<double> values(n * static_cast<std::size_t>(size));
    H5Dread(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
    values[1] = std::nextafter(values[1], 1.0);
    H5Dwrite(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
    H5Dclose(dataset);
    H5Fclose(h5);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  ASSERT_TRUE(checkpoints.latest().has_value());
  EXPECT_EQ(checkpoints.latest()->filename().string(), "step_000000010.h5");

  // A newer checkpoint of another case: refused, naming the file and the key.
  const Checkpoints other(MPI_COMM_WORLD, dir,
                          CheckpointSettings{10, 3, "model = 'lumped'\nvalve.max_area_fraction = 0.5\n"});
  other.write({30, 0.03, 30}, [&](Hdf5File& h5) { save_block(h5, rank, size, block_of(rank, n, 30.0)); });
  try {
    checkpoints.latest();
    ADD_FAILURE() << "a checkpoint of another case was accepted";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("step_000000030.h5"), std::string::npos) << message;
    EXPECT_NE(message.find("valve.max_area_fraction is 0.5 there but 0.6 here"), std::string::npos)
        << message;
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank == 0) std::filesystem::remove_all(dir);
}

TEST(Checkpoints, TheRecordMarksTheKeysLeftAtTheirDefault)
{
  Schema schema;
  schema.add_string("model", "model").required().example(std::string("lumped"));
  schema.add_real("valve.max_area_fraction", "largest area").defaults(0.6);
  schema.add_real("valve.min_area_fraction", "smallest area").defaults(0.01);
  toml::table table = toml::parse("model = 'lumped'\nvalve.max_area_fraction = 0.5\n");
  const Config config = Config::validate(std::move(table), "case.toml", schema);
  EXPECT_EQ(case_record(config), "model = 'lumped'\nvalve.max_area_fraction = 0.5\n"
                                 "valve.min_area_fraction = 0.01  (default)\n");
}

TEST(Checkpoints, AKeyANewerBuildAddedContinuesAnOlderRunOnlyAtItsDefault)
{
  const auto [rank, size] = world();
  const auto dir = shared_run_directory("newkey");
  // Written by a build without valve.min_area_fraction (and without default marks).
  const std::string older = "model = 'lumped'\nvalve.max_area_fraction = 0.6\n";
  const Checkpoints writer(MPI_COMM_WORLD, dir, CheckpointSettings{10, 3, older});
  writer.write({10, 0.01, 10}, [&](Hdf5File& h5) { save_block(h5, rank, size, block_of(rank, 5, 10.0)); });

  // The newer build's record of the same case: the new key at its default, the old one marked too.
  const Checkpoints at_default(
      MPI_COMM_WORLD, dir,
      CheckpointSettings{10, 3,
                         "model = 'lumped'\nvalve.max_area_fraction = 0.6  (default)\n"
                         "valve.min_area_fraction = 0.01  (default)\n"});
  ASSERT_TRUE(at_default.latest().has_value());
  EXPECT_EQ(at_default.latest()->filename().string(), "step_000000010.h5");

  // The new key set away from its default changes the case: refused, naming it.
  const Checkpoints set(MPI_COMM_WORLD, dir,
                        CheckpointSettings{10, 3,
                                           "model = 'lumped'\nvalve.max_area_fraction = 0.6  (default)\n"
                                           "valve.min_area_fraction = 0.02\n"});
  try {
    set.latest();
    ADD_FAILURE() << "a checkpoint of another case was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("valve.min_area_fraction is not set there but 0.02 here"),
              std::string::npos)
        << e.what();
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank == 0) std::filesystem::remove_all(dir);
}

TEST(Checkpoints, TimeSeriesIsCutBackToTheRecordedRows)
{
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank != 0) return; // a file operation of one rank
  const auto path =
      std::filesystem::temp_directory_path() / (fmt::format("ibvalve_ckpt_rows_{}.csv", ::getpid()));
  write_file_atomically(path, "t,q\n0,1\n# a comment\n1,2\n2,3\n3,4\n");
  truncate_csv_rows(path, 2);
  EXPECT_EQ(read_text_file(path), "t,q\n0,1\n# a comment\n1,2\n");
  EXPECT_THROW(truncate_csv_rows(path, 5), InputError);
  std::filesystem::remove(path);
}

} // namespace
} // namespace ibvalve::io
