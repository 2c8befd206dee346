// Parallel HDF5: a global array written in blocks by every rank reads back whole and in blocks, on 1
// and 2 ranks; data from rank 0 is written once; the XDMF text points at the datasets.
#include <filesystem>
#include <fmt/format.h>
#include <numeric>

#include <gtest/gtest.h>
#include <mpi.h>

#include "base/errors.hpp"
#include "io/files.hpp"
#include "io/hdf5.hpp"
#include "io/xdmf.hpp"

namespace ibvalve::io {
namespace {

std::filesystem::path shared_temp_path(const std::string& name)
{
  // Every rank must name the same file: rank 0's process id decides.
  int pid = static_cast<int>(::getpid());
  MPI_Bcast(&pid, 1, MPI_INT, 0, MPI_COMM_WORLD);
  return std::filesystem::temp_directory_path() / (fmt::format("ibvalve_{}_{}.h5", name, pid));
}

TEST(Hdf5File, BlocksFromEveryRankMakeOneGlobalArray)
{
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const hsize_t rows_per_rank = 3, columns = 4;
  const std::vector<hsize_t> global{rows_per_rank * size, columns};
  const std::vector<hsize_t> offset{rows_per_rank * rank, 0};
  const std::vector<hsize_t> count{rows_per_rank, columns};
  std::vector<double> block(rows_per_rank * columns);
  for (hsize_t i = 0; i < rows_per_rank; ++i)
    for (hsize_t j = 0; j < columns; ++j) block[i * columns + j] = 100.0 * (offset[0] + i) + j;

  const auto path = shared_temp_path("blocks");
  {
    Hdf5File file(MPI_COMM_WORLD, path, Hdf5File::Mode::create);
    file.write_block("fields/u", block, global, offset, count);
    const std::vector<std::int64_t> connectivity{0, 1, 2, 3};
    file.write_root("mesh/connectivity", std::span<const std::int64_t>(connectivity),
                    std::vector<hsize_t>{1, 4});
    file.write_attribute("time", 0.25);
  }
  {
    Hdf5File file(MPI_COMM_WORLD, path, Hdf5File::Mode::read);
    EXPECT_EQ(file.dims("fields/u"), global);
    const auto whole = file.read("fields/u");
    for (hsize_t i = 0; i < global[0]; ++i)
      for (hsize_t j = 0; j < columns; ++j) EXPECT_EQ(whole[i * columns + j], 100.0 * i + j);
    EXPECT_EQ(file.read_block("fields/u", offset, count), block);
    EXPECT_EQ(file.read_integers("mesh/connectivity"), (std::vector<std::int64_t>{0, 1, 2, 3}));
    EXPECT_DOUBLE_EQ(file.read_attribute("time"), 0.25);
    EXPECT_FALSE(file.has("fields/p"));
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank == 0) std::filesystem::remove(path);
}

TEST(Hdf5File, AFileRankZeroCannotWriteFailsOnEveryRank)
{
  // Rank 0 writes the file at close(); its failure (here: no such folder; a full disk alike) is one
  // RunError naming the file and the OS reason on every rank, and no rank is left waiting.
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const std::vector<double> block{1.0, 2.0};
  const std::vector<hsize_t> global{2 * static_cast<hsize_t>(size)}, offset{2 * static_cast<hsize_t>(rank)},
      count{2};
  Hdf5File file(MPI_COMM_WORLD, "/nonexistent_folder/fields.h5", Hdf5File::Mode::create);
  file.write_block("u", block, global, offset, count);
  file.write_attribute("time", 0.5);
  try {
    file.close();
    FAIL() << "no error";
  } catch (const RunError& error) {
    EXPECT_EQ(std::string(error.what()),
              "/nonexistent_folder/fields.h5: cannot write: No such file or directory");
  }
}

TEST(Hdf5File, AnImageInMemoryReadsBackOnEveryRankAndTouchesNoDisk)
{
  // Mode::memory builds the file as create mode does but close() keeps it on rank 0 (a run's state to
  // go back to within an interval); the image reads back whole and in blocks on every rank.
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const hsize_t rows_per_rank = 5, columns = 3;
  const std::vector<hsize_t> global{rows_per_rank * size, columns}, offset{rows_per_rank * rank, 0},
      count{rows_per_rank, columns};
  std::vector<double> block(rows_per_rank * columns);
  for (std::size_t i = 0; i < block.size(); ++i) block[i] = 0.1 * static_cast<double>(i) + rank;
  const auto path = shared_temp_path("memory");
  std::vector<char> image;
  {
    Hdf5File file(MPI_COMM_WORLD, path, Hdf5File::Mode::memory);
    file.write_block("fluid/u", block, global, offset, count);
    file.write_root("ibfe/x", std::vector<double>{1.5, -2.5}, std::vector<hsize_t>{2});
    file.close();
    image = file.take_image();
  }
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_EQ(image.empty(), rank != 0);
  const Hdf5File file(MPI_COMM_WORLD, "the state", image);
  EXPECT_EQ(file.read_block("fluid/u", offset, count), block);
  EXPECT_EQ(file.read("fluid/u").size(), global[0] * columns);
  EXPECT_EQ(file.read("ibfe/x"), (std::vector<double>{1.5, -2.5}));
  EXPECT_THROW(file.read("fluid/p"), std::runtime_error);
}

TEST(Hdf5File, OpeningAMissingFileThrows)
{
  EXPECT_THROW(Hdf5File(MPI_COMM_WORLD, "/nonexistent/x.h5", Hdf5File::Mode::read), std::runtime_error);
}

TEST(XdmfTimeSeries, DescribesRegularGridsAndMeshesPerTime)
{
  XdmfTimeSeries series(MPI_COMM_WORLD, shared_temp_path("series").replace_extension(".xdmf"));
  auto fluid = XdmfGrid::regular("fluid", {4, 5, 6}, {0, 0, 0}, {0.25, 0.2, 0.1});
  fluid.add_field("pressure", Center::cell, {6, 5, 4}, "f.h5:/p")
      .add_field("velocity", Center::cell, {6, 5, 4, 3}, "f.h5:/u");
  auto mesh = XdmfGrid::mesh("valve", "Hexahedron", 2, 8, "m.h5:/cells", 12, "m.h5:/x");
  mesh.add_field("J", Center::cell, {2}, "m.h5:/J");
  series.add_step(0.5, {fluid, mesh});
  const std::string text = series.text();
  EXPECT_NE(text.find("<Time Value=\"0.5\"/>"), std::string::npos);
  EXPECT_NE(text.find("TopologyType=\"3DCoRectMesh\" Dimensions=\"7 6 5\""), std::string::npos);
  EXPECT_NE(text.find("AttributeType=\"Vector\" Center=\"Cell\""), std::string::npos);
  EXPECT_NE(text.find("TopologyType=\"Hexahedron\" NumberOfElements=\"2\""), std::string::npos);
  EXPECT_NE(text.find("Dimensions=\"12 3\""), std::string::npos);
  series.add_step(1.0, {fluid});
  series.drop_after(0.5);
  EXPECT_EQ(series.steps(), 1u);
}

TEST(XdmfTimeSeries, EachTimeIsOneGridNamedTheSameAtEveryTime)
{
  // ParaView names a block after the grid of its time: a name that changed with the time (a step's
  // "t = 0.5") made another block at every time. One grid is the time's grid itself; several (the level
  // boxes of nested levels) a spatial collection named after the series.
  const auto count = [](const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
  };
  // Collective: every rank names the files (shared_temp_path broadcasts).
  const auto one_path = shared_temp_path("one").replace_extension(".xdmf");
  const auto levels_path = shared_temp_path("levels").replace_extension(".xdmf");
  XdmfTimeSeries structure(MPI_COMM_WORLD, one_path, "structure");
  const auto mesh = XdmfGrid::mesh("structure", "Hexahedron", 2, 8, "m.h5:/cells", 12, "m.h5:/x");
  structure.add_step(0.0, {mesh});
  structure.add_step(0.5, {mesh});
  const std::string one = structure.text();
  EXPECT_EQ(count(one, "<Grid Name=\"structure\" GridType=\"Uniform\">\n        <Time Value="), 2u) << one;
  EXPECT_EQ(count(one, "<Grid "), 3u) << one; // the temporal collection and a grid per time
  EXPECT_EQ(count(one, "t = "), 0u) << one;

  XdmfTimeSeries fluid(MPI_COMM_WORLD, levels_path, "fluid");
  const auto coarse = XdmfGrid::regular("fluid_level0_box0", {4, 4, 4}, {0, 0, 0}, {0.5, 0.5, 0.5});
  const auto fine = XdmfGrid::regular("fluid_level1_box0", {4, 4, 4}, {0.5, 0.5, 0.5}, {0.25, 0.25, 0.25});
  fluid.add_step(0.0, {coarse, fine});
  fluid.add_step(0.5, {coarse, fine});
  const std::string levels = fluid.text();
  EXPECT_EQ(count(levels, "<Grid Name=\"fluid\" GridType=\"Collection\" CollectionType=\"Spatial\">"), 2u)
      << levels;
  EXPECT_EQ(count(levels, "<Grid Name=\"fluid_level1_box0\" GridType=\"Uniform\">"), 2u) << levels;
  EXPECT_EQ(count(levels, "t = "), 0u) << levels;
  MPI_Barrier(MPI_COMM_WORLD);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0)
    for (const auto& path : {one_path, levels_path}) std::filesystem::remove(path);
}

TEST(Hdf5File, DatasetsCarryStringAttributes)
{
  // Every rank makes the same attribute call (rank 0 writes the file); every rank reads it back. An
  // attribute of a dataset the file lacks fails the file on every rank when it is closed, as any
  // failed write does.
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  const auto path = shared_temp_path("units");
  {
    Hdf5File file(MPI_COMM_WORLD, path, Hdf5File::Mode::create);
    const std::vector<double> p{1.0, 2.0};
    file.write_root("fluid/pressure", p, std::vector<hsize_t>{2});
    file.write_string_attribute("fluid/pressure", "units", "dyn/cm^2");
    file.close();
  }
  {
    const auto wrong = shared_temp_path("units_missing");
    Hdf5File file(MPI_COMM_WORLD, wrong, Hdf5File::Mode::create);
    file.write_string_attribute("fluid/none", "units", "cm");
    EXPECT_THROW(file.close(), std::runtime_error);
    EXPECT_FALSE(std::filesystem::exists(wrong));
  }
  {
    Hdf5File file(MPI_COMM_WORLD, path, Hdf5File::Mode::read);
    EXPECT_EQ(file.read_string_attribute("fluid/pressure", "units"), "dyn/cm^2");
    EXPECT_THROW(file.read_string_attribute("fluid/pressure", "description"), std::runtime_error);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank == 0) std::filesystem::remove(path);
}

TEST(XdmfTimeSeries, NamesCarryUnitsAndGridsCarryInformation)
{
  // What ParaView lists: "velocity [cm/s]"; a pure number or a label keeps its bare name. Information
  // text from a user's mesh (part names) is escaped, so the file stays XML.
  const auto path = shared_temp_path("units").replace_extension(".xdmf"); // collective: once, on every rank
  XdmfTimeSeries series(MPI_COMM_WORLD, path);
  auto mesh = XdmfGrid::mesh("structure", "Hexahedron", 2, 8, "m.h5:/cells", 12, "m.h5:/x");
  mesh.add_information("part", "1 = leaflet<1>, 2 = \"tube\" & wall")
      .add_field("velocity", Center::node, {12, 3}, "m.h5:/v", "cm/s")
      .add_field("J", Center::cell, {2}, "m.h5:/J", "1")
      .add_field("part", Center::cell, {2}, "m.h5:/part", "", true);
  series.add_step(0.0, {mesh});
  const std::string text = series.text();
  EXPECT_NE(text.find("<Attribute Name=\"velocity [cm/s]\" AttributeType=\"Vector\" Center=\"Node\">"),
            std::string::npos);
  EXPECT_NE(text.find("<Attribute Name=\"J\" "), std::string::npos);
  EXPECT_NE(text.find("Dimensions=\"2\" NumberType=\"Int\" Precision=\"8\" Format=\"HDF\">m.h5:/part<"),
            std::string::npos);
  EXPECT_NE(
      text.find(
          "<Information Name=\"part\" Value=\"1 = leaflet&lt;1&gt;, 2 = &quot;tube&quot; &amp; wall\"/>"),
      std::string::npos);
  MPI_Barrier(MPI_COMM_WORLD);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0) std::filesystem::remove(path);
}

TEST(XdmfTimeSeries, ResumeTakesOverTheStepsUpToTheCheckpointFromTheFile)
{
  // A run wrote outputs at t = 0, 1/3 and 2/3 and was stopped; its checkpoint is at t = 1/3 (a time
  // that only 17 digits give back exactly). The restarted run's series starts from the file.
  const auto path = shared_temp_path("resume").replace_extension(".xdmf");
  auto fluid = XdmfGrid::regular("fluid", {4, 5, 6}, {0, 0, 0}, {0.25, 0.2, 0.1});
  fluid.add_field("velocity", Center::cell, {6, 5, 4, 3}, "f.h5:/u");
  auto mesh = XdmfGrid::mesh("valve", "Hexahedron", 2, 8, "m.h5:/cells", 12, "m.h5:/x");
  const double third = 1.0 / 3.0;
  {
    XdmfTimeSeries interrupted(MPI_COMM_WORLD, path);
    interrupted.add_step(0.0, {fluid, mesh});
    interrupted.add_step(third, {fluid, mesh});
    interrupted.add_step(2.0 * third, {fluid, mesh});
  }
  XdmfTimeSeries expected(MPI_COMM_WORLD, shared_temp_path("expected").replace_extension(".xdmf"));
  expected.add_step(0.0, {fluid, mesh});
  expected.add_step(third, {fluid, mesh});
  expected.add_step(1.0, {fluid});

  XdmfTimeSeries resumed(MPI_COMM_WORLD, path);
  resumed.resume(third);
  EXPECT_EQ(resumed.steps(), 2u);
  resumed.add_step(1.0, {fluid});
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0) {
    EXPECT_EQ(resumed.text(), expected.text());
    EXPECT_EQ(read_text_file(path), expected.text());
  }
  // A series with no file yet (a restart before the first output) resumes with no steps.
  XdmfTimeSeries fresh(MPI_COMM_WORLD, shared_temp_path("none").replace_extension(".xdmf"));
  fresh.resume(1.0);
  EXPECT_EQ(fresh.steps(), 0u);
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank == 0)
    for (const char* name : {"resume", "expected", "none"})
      std::filesystem::remove(shared_temp_path(name).replace_extension(".xdmf"));
}

} // namespace
} // namespace ibvalve::io
