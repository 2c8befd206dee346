// Composite cell fields written per level box (fluid/composite_output.hpp), read back on every rank:
// uncovered cells hold the composite values, covered cells the volume average of the finer cells (exact for
// a linear field; X^2 + (H/4)^2 for x^2 under one ratio-2 level), and the XDMF names one grid per level box.
// The velocity of a MAC field is written at cell centres as the mean of each cell's two faces.
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "fluid/composite_output.hpp"
#include "fluid/composite_velocity.hpp"
#include "io/petsc_check.hpp"

namespace ibvalve::fluid {
namespace {

int world_rank()
{
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  return rank;
}

std::string file_text(const std::string& path)
{
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The unit box, 8^3 cells; level 1: cells [2,6)^3 of level 0 refined by 2 (two boxes side by side);
// level 2 inside it, ratio 2.
GridHierarchy three_levels()
{
  BoxGeometry box;
  box.cells = {8, 8, 8};
  box.periodic = {false, false, false};
  return GridHierarchy(box,
                       {FinerLevel{2, {IndexBox{{4, 4, 4}, {8, 12, 12}}, IndexBox{{8, 4, 4}, {12, 12, 12}}}},
                        FinerLevel{2, {IndexBox{{12, 12, 12}, {20, 20, 20}}}}});
}

double linear(const Real3& x)
{
  return 1.0 + x[0] + 2.0 * x[1] - 3.0 * x[2];
}
double square(const Real3& x)
{
  return x[0] * x[0];
}

TEST(CompositeOutput, EveryLevelBoxWithCoveredCellsAveragedFromTheFinerLevels)
{
  const GridHierarchy h = three_levels();
  const CompositeOperators ops(PETSC_COMM_WORLD, h, CoarseFineStencil::tangential_linear,
                               CompositeBoundary::neumann);
  const petsc::OwnedVec a = ops.create_cell_vector(), b = ops.create_cell_vector();
  ops.sample(linear, a);
  ops.sample(square, b);
  const std::string name = "composite_output_test";
  std::vector<io::XdmfGrid> grids;
  {
    io::Hdf5File file(PETSC_COMM_WORLD, name + ".h5", io::Hdf5File::Mode::create);
    grids = write_composite_fields(file, ops.cells(), {{"linear", a}, {"square", b}}, "t0", name + ".h5");
  }
  io::XdmfTimeSeries series(PETSC_COMM_WORLD, name + ".xdmf");
  series.add_step(0.0, grids);
  ASSERT_EQ(grids.size(), 4u);

  io::Hdf5File file(PETSC_COMM_WORLD, name + ".h5", io::Hdf5File::Mode::read);
  double worst_linear = 0.0;
  for (int l = 0; l < h.levels(); ++l)
    for (std::size_t bi = 0; bi < h.boxes(l).size(); ++bi) {
      const IndexBox& ib = h.boxes(l)[bi];
      const std::string group = fmt::format("t0/level{}_box{}/", l, bi);
      const auto dims = file.dims(group + "linear");
      ASSERT_EQ(dims.size(), 3u);
      EXPECT_EQ(dims[0], static_cast<hsize_t>(ib.cells(2)));
      EXPECT_EQ(dims[2], static_cast<hsize_t>(ib.cells(0)));
      const auto lin = file.read(group + "linear");
      const auto sq = file.read(group + "square");
      for (PetscInt k = ib.lower[2]; k < ib.upper[2]; ++k)
        for (PetscInt j = ib.lower[1]; j < ib.upper[1]; ++j)
          for (PetscInt i = ib.lower[0]; i < ib.upper[0]; ++i) {
            const Real3 x = h.cell_center(l, {i, j, k});
            const PetscInt o = ib.offset({i, j, k});
            worst_linear = std::max(worst_linear, std::abs(lin[o] - linear(x)));
            // Under level 1 only (not level 2): the average of 8 fine centres at X +- H/4.
            if (l == 0 && h.covered(0, {i, j, k}) && !h.covered(1, {2 * i, 2 * j, 2 * k})) {
              const double H = h.h(0, 0);
              EXPECT_NEAR(sq[o], x[0] * x[0] + H * H / 16.0, 1e-14) << i << " " << j << " " << k;
            }
            if (!h.covered(l, {i, j, k})) {
              EXPECT_NEAR(sq[o], square(x), 1e-15);
            }
          }
    }
  EXPECT_LE(worst_linear, 1e-13);

  if (world_rank() == 0) {
    const std::string text = file_text(name + ".xdmf");
    for (const char* grid : {"level0_box0", "level1_box0", "level1_box1", "level2_box0"})
      EXPECT_NE(text.find(grid), std::string::npos) << grid;
    EXPECT_NE(text.find(name + ".h5:/t0/level2_box0/square"), std::string::npos);
  }
}

// u = (x(1-x), 2 y(1-y), 0) on the unit box: its normal part is zero on every wall (a closed box), and the
// mean of the two faces of a cell of width h is exact up to f''h^2/8: x(1-x) - h^2/4 for the first
// component, 2 y(1-y) - h^2/2 for the second. A level-0 cell covered by level 1 only holds the mean of its
// 8 fine cells (width h = H/2, centres X +- H/4): X(1-X) - H^2/16 - h^2/4 = X(1-X) - H^2/8.
TEST(CompositeOutput, CellCentredVelocityOnEveryLevelIsTheMeanOfEachCellsFaces)
{
  const GridHierarchy h = three_levels();
  const CompositeOperators ops(PETSC_COMM_WORLD, h, CoarseFineStencil::two_point, CompositeBoundary::neumann);
  const CompositeVelocity velocity(ops);
  auto field = [](const Real3& x) { return Real3{x[0] * (1.0 - x[0]), 2.0 * x[1] * (1.0 - x[1]), 0.0}; };
  const petsc::OwnedVec u = ops.create_face_vector();
  ops.sample_normal(field, u);
  std::array<petsc::OwnedVec, 3> owned_cells;
  std::array<Vec, 3> cells{};
  for (std::size_t c = 0; c < 3; ++c) {
    owned_cells[c] = ops.create_cell_vector();
    cells[c] = owned_cells[c];
  }
  velocity.cell_velocity(u, {}, 0.0, cells);
  const std::string name = "composite_velocity_output_test";
  std::vector<io::XdmfGrid> grids;
  {
    io::Hdf5File file(PETSC_COMM_WORLD, name + ".h5", io::Hdf5File::Mode::create);
    grids = write_composite_fields(file, ops.cells(), {}, "t0", name + ".h5", "", {{"velocity", cells}});
  }
  io::XdmfTimeSeries series(PETSC_COMM_WORLD, name + ".xdmf");
  series.add_step(0.0, grids);
  ASSERT_EQ(grids.size(), 4u);
  io::Hdf5File file(PETSC_COMM_WORLD, name + ".h5", io::Hdf5File::Mode::read);
  double worst = 0.0;
  int checked_covered = 0;
  for (int l = 0; l < h.levels(); ++l)
    for (std::size_t bi = 0; bi < h.boxes(l).size(); ++bi) {
      const IndexBox& ib = h.boxes(l)[bi];
      const std::string dataset = fmt::format("t0/level{}_box{}/velocity", l, bi);
      const auto dims = file.dims(dataset);
      ASSERT_EQ(dims.size(), 4u);
      EXPECT_EQ(dims[3], 3u);
      const auto v = file.read(dataset);
      const double hl = h.h(l, 0);
      for (PetscInt k = ib.lower[2]; k < ib.upper[2]; ++k)
        for (PetscInt j = ib.lower[1]; j < ib.upper[1]; ++j)
          for (PetscInt i = ib.lower[0]; i < ib.upper[0]; ++i) {
            const Real3 x = h.cell_center(l, {i, j, k});
            const std::size_t o = 3 * static_cast<std::size_t>(ib.offset({i, j, k}));
            if (!h.covered(l, {i, j, k})) {
              worst = std::max({worst, std::abs(v[o] - (field(x)[0] - hl * hl / 4.0)),
                                std::abs(v[o + 1] - (field(x)[1] - hl * hl / 2.0)), std::abs(v[o + 2])});
            } else if (l == 0 && !h.covered(1, {2 * i, 2 * j, 2 * k})) {
              EXPECT_NEAR(v[o], field(x)[0] - hl * hl / 8.0, 1e-14) << i << " " << j << " " << k;
              ++checked_covered;
            }
          }
    }
  EXPECT_LE(worst, 1e-14);
  EXPECT_GT(checked_covered, 0);
  if (world_rank() == 0) {
    const std::string text = file_text(name + ".xdmf");
    EXPECT_NE(text.find("AttributeType=\"Vector\""), std::string::npos);
    EXPECT_NE(text.find(name + ".h5:/t0/level2_box0/velocity"), std::string::npos);
  }
}

} // namespace
} // namespace ibvalve::fluid
