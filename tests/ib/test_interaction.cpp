// Interpolation and spreading on the distributed staggered grid: adjointness to round-off for every
// kernel on periodic and walled boxes (points straddling the ranks' boundaries and the periodic
// seams), exact interpolation of linear fields, conservation of the total force, and a clear error
// for a point that leaves the box. Run on 1 and 2 ranks.
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <mpi.h>

#include "base/errors.hpp"
#include "fluid/grid.hpp"
#include "ib/interaction.hpp"

using namespace ibvalve;
using ib::Vec3;

namespace {

const ib::KernelKind all_kernels[] = {ib::KernelKind::piecewise_linear, ib::KernelKind::ib_3,
                                      ib::KernelKind::ib_4, ib::KernelKind::ib_6, ib::KernelKind::bspline_3};

fluid::BoxGeometry box(bool periodic)
{
  fluid::BoxGeometry b;
  b.lower = {-0.5, 0.0, 0.25};
  b.upper = {0.7, 1.0, 1.05};
  b.cells = {12, 10, 8};
  b.periodic = {periodic, periodic, periodic};
  return b;
}

// A face field that depends on the face's global index only, so every decomposition sees the same one.
double face_value(int d, PetscInt i, PetscInt j, PetscInt k)
{
  const double x = 0.37 * d + 0.113 * i + 0.271 * j + 0.197 * k;
  return std::sin(11.0 * x) + 0.5 * std::cos(7.0 * x * x);
}

void fill_faces(const fluid::StaggeredGrid& g, Vec v,
                const std::function<double(int, PetscInt, PetscInt, PetscInt)>& f)
{
  fluid::StagArray a(g, v);
  for (int d = 0; d < 3; ++d)
    for (PetscInt k = g.begin(2); k < g.face_end(d, 2); ++k)
      for (PetscInt j = g.begin(1); j < g.face_end(d, 1); ++j)
        for (PetscInt i = g.begin(0); i < g.face_end(d, 0); ++i) a(i, j, k, g.face_slot(d)) = f(d, i, j, k);
}

// Points crowded around the middle planes (where 2 ranks meet), near the box sides (periodic seams or
// walls) and scattered; the same on every rank.
std::vector<Vec3> points(const fluid::BoxGeometry& b, bool include_outside_images)
{
  std::mt19937 gen(11);
  std::vector<Vec3> x;
  std::uniform_real_distribution<double> unit(0.0, 1.0), near(-2.0, 2.0);
  for (int n = 0; n < 200; ++n) {
    Vec3 p;
    for (int d = 0; d < 3; ++d) p[d] = b.lower[d] + unit(gen) * b.length(d);
    const int d = n % 3;
    if (n % 4 == 0) p[d] = 0.5 * (b.lower[d] + b.upper[d]) + near(gen) * b.spacing(d);
    if (n % 4 == 1) p[d] = b.lower[d] + std::abs(near(gen)) * b.spacing(d);
    if (n % 4 == 2) p[d] = b.upper[d] - std::abs(near(gen)) * b.spacing(d);
    if (include_outside_images && n % 10 == 3) p[d] += b.length(d);
    x.push_back(p);
  }
  return x;
}

std::vector<Vec3> sum_over_ranks(std::vector<Vec3> v, MPI_Comm comm)
{
  MPI_Allreduce(MPI_IN_PLACE, v.data(), static_cast<int>(3 * v.size()), MPI_DOUBLE, MPI_SUM, comm);
  return v;
}

} // namespace

class Adjointness : public ::testing::TestWithParam<bool> {};

TEST_P(Adjointness, SpreadThenDotEqualsDotOfInterpolation)
{
  const bool periodic = GetParam();
  const fluid::BoxGeometry b = box(periodic);
  fluid::StaggeredGrid grid(PETSC_COMM_WORLD, b);
  const petsc::OwnedVec u = grid.create_local(), f = grid.create_local();
  fill_faces(grid, u, face_value);
  const std::vector<Vec3> x = points(b, periodic);
  std::vector<Vec3> F(x.size());
  for (std::size_t p = 0; p < x.size(); ++p)
    F[p] = Vec3(std::cos(p + 1.0), std::sin(2.0 * p), 0.3 - 0.01 * p);
  for (ib::KernelKind kind : all_kernels) {
    ib::GridInteraction interaction(grid, kind);
    std::vector<Vec3> Ju(x.size());
    interaction.interpolate(u, x, Ju);
    Ju = sum_over_ranks(Ju, grid.comm());
    interaction.spread(x, F, f);
    const double grid_side = interaction.inner_product(f, u);
    double point_side = 0.0, magnitude = 0.0;
    for (std::size_t p = 0; p < x.size(); ++p) {
      point_side += F[p].dot(Ju[p]);
      magnitude += F[p].norm() * Ju[p].norm();
    }
    EXPECT_GT(std::abs(point_side), 1e-3 * magnitude) << "the test must not be close to 0 = 0";
    EXPECT_LT(std::abs(grid_side - point_side), 1e-12 * std::abs(point_side))
        << interaction.kernel().name() << (periodic ? " periodic" : " walls") << ": " << grid_side << " vs "
        << point_side;
  }
}

INSTANTIATE_TEST_SUITE_P(PeriodicAndWalled, Adjointness, ::testing::Values(true, false));

TEST(Interpolation, LinearFieldsAreInterpolatedExactlyByEveryKernel)
{
  // Away from the walls (by the kernel's half support) each kernel's first moment makes the
  // interpolant of u_d = a_d + B_d . x exact.
  fluid::BoxGeometry b = box(false);
  b.cells = {24, 20, 16};
  fluid::StaggeredGrid grid(PETSC_COMM_WORLD, b);
  const Eigen::Matrix3d B{{0.3, -1.2, 2.0}, {0.7, 0.1, -0.4}, {-1.5, 0.9, 0.25}};
  const Vec3 a0(0.5, -0.25, 1.0);
  const petsc::OwnedVec u = grid.create_local();
  fill_faces(grid, u, [&](int d, PetscInt i, PetscInt j, PetscInt k) {
    const auto p = grid.face_position(d, i, j, k);
    return a0[d] + B.row(d).dot(Vec3(p[0], p[1], p[2]));
  });
  std::mt19937 gen(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Vec3> x;
  for (int n = 0; n < 100; ++n) {
    Vec3 p;
    for (int d = 0; d < 3; ++d)
      p[d] = b.lower[d] + 3.5 * b.spacing(d) + unit(gen) * (b.length(d) - 7.0 * b.spacing(d));
    x.push_back(p);
  }
  for (ib::KernelKind kind : all_kernels) {
    ib::GridInteraction interaction(grid, kind);
    std::vector<Vec3> v(x.size());
    interaction.interpolate(u, x, v);
    v = sum_over_ranks(v, grid.comm());
    double worst = 0.0;
    for (std::size_t p = 0; p < x.size(); ++p)
      worst = std::max(worst, (v[p] - (a0 + B * x[p])).cwiseAbs().maxCoeff());
    EXPECT_LT(worst, 1e-13) << interaction.kernel().name();
  }
}

TEST(Spreading, TotalForceIsConservedInAPeriodicBox)
{
  const fluid::BoxGeometry b = box(true);
  fluid::StaggeredGrid grid(PETSC_COMM_WORLD, b);
  const std::vector<Vec3> x = points(b, true);
  std::vector<Vec3> F(x.size());
  Vec3 total = Vec3::Zero();
  for (std::size_t p = 0; p < x.size(); ++p)
    total += (F[p] = Vec3(1.0 + p % 3, -0.5 * p, std::sqrt(p + 2.0)));
  const petsc::OwnedVec f = grid.create_local(), one = grid.create_local();
  for (ib::KernelKind kind : all_kernels) {
    ib::GridInteraction interaction(grid, kind);
    interaction.spread(x, F, f);
    for (int d = 0; d < 3; ++d) {
      fill_faces(grid, one, [d](int c, PetscInt, PetscInt, PetscInt) { return c == d ? 1.0 : 0.0; });
      EXPECT_NEAR(interaction.inner_product(f, one), total[d], 1e-12 * total.norm())
          << interaction.kernel().name();
    }
  }
}

TEST(Interaction, APointOutsideAWalledBoxIsARunErrorNamingTheDirection)
{
  const fluid::BoxGeometry b = box(false);
  fluid::StaggeredGrid grid(PETSC_COMM_WORLD, b);
  ib::GridInteraction interaction(grid);
  const petsc::OwnedVec u = grid.create_local();
  std::vector<Vec3> x{Vec3(0.0, 0.5, 0.5), Vec3(0.0, 1.01, 0.5)}, v(2);
  try {
    interaction.interpolate(u, x, v);
    ADD_FAILURE() << "no error";
  } catch (const RunError& e) {
    EXPECT_NE(std::string(e.what()).find("left the grid: direction y"), std::string::npos) << e.what();
  }
  x[1] = Vec3(0.0, std::nan(""), 0.5);
  EXPECT_THROW(interaction.interpolate(u, x, v), RunError);
}

// A rank places only the points of elements whose nodes' bounding box may hold points it handles
// (GridInteraction::may_hold): no point inside a box it rules out may be one it owns, on walled and
// periodic boxes alike, and a box reaching outside a walled side is kept on every rank so that the
// point's error reaches all of them.
TEST(Interaction, ABoxRuledOutHoldsNoPointThisRankHandles)
{
  for (const bool periodic : {false, true}) {
    const fluid::BoxGeometry b = box(periodic);
    fluid::StaggeredGrid grid(PETSC_COMM_WORLD, b);
    ib::GridInteraction interaction(grid);
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int ruled_out = 0;
    for (int trial = 0; trial < 2000; ++trial) {
      Vec3 lower, upper;
      for (int d = 0; d < 3; ++d) {
        const double a = b.lower[d] + unit(random) * b.length(d), size = 0.3 * unit(random) * b.length(d);
        lower[d] = std::max(b.lower[d], a - size);
        upper[d] = std::min(b.upper[d], a + size);
      }
      if (interaction.may_hold(lower, upper)) continue;
      ++ruled_out;
      // Corners, faces and the inside of the box, as an element's points would lie.
      for (int m = 0; m < 64; ++m) {
        Vec3 x;
        for (int d = 0; d < 3; ++d) {
          const double t = m < 8 ? double((m >> d) & 1) : unit(random);
          x[d] = lower[d] + t * (upper[d] - lower[d]);
        }
        ASSERT_FALSE(interaction.owns(x)) << "a point of a ruled-out box is this rank's: " << x.transpose();
      }
    }
    int size = 1;
    MPI_Comm_size(PETSC_COMM_WORLD, &size);
    if (size > 1 && !periodic) {
      EXPECT_GT(ruled_out, 100); // the test tested something
    }
    // Outside a walled side, or not finite: kept everywhere.
    if (!periodic) {
      EXPECT_TRUE(interaction.may_hold(Vec3(0.0, 0.5, 0.5), Vec3(0.1, 1.01, 0.6)));
      EXPECT_TRUE(interaction.may_hold(Vec3(0.0, std::nan(""), 0.5), Vec3(0.1, 0.6, 0.6)));
    }
  }
}

// Preparing the listed candidates gives the same points, in the same order, with the same stencils
// as preparing every point, when the candidates include every point this rank handles.
TEST(Interaction, PreparingCandidatesEqualsPreparingEveryPoint)
{
  const fluid::BoxGeometry b = box(false);
  fluid::StaggeredGrid grid(PETSC_COMM_WORLD, b);
  ib::GridInteraction interaction(grid);
  const std::vector<Vec3> x = points(b, false);
  std::vector<std::size_t> candidates;
  for (std::size_t p = 0; p < x.size(); ++p)
    if (interaction.owns(x[p]) || p % 3 == 0) candidates.push_back(p);
  ib::GridInteraction::PreparedPoints all, listed;
  interaction.prepare(x, all);
  interaction.prepare(x, candidates, listed);
  EXPECT_EQ(all.index, listed.index);
  const petsc::OwnedVec u = grid.create_local();
  fill_faces(grid, u, face_value);
  std::vector<Vec3> from_all(all.size()), from_listed(listed.size());
  interaction.interpolate(u, all, from_all);
  interaction.interpolate(u, listed, from_listed);
  for (std::size_t i = 0; i < from_all.size(); ++i) EXPECT_EQ(from_all[i], from_listed[i]);
}
