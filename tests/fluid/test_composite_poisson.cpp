// Composite-grid cell-centred operators (fluid/composite_poisson.hpp) on nested levels:
//  - the assembled pressure operator A = G^T W G is symmetric, |x.Ay - y.Ax| <= 1e-12 |x||A||y|;
//  - the adjoint divergence is conservative: the discrete divergence theorem holds over the whole box and,
//    for the two-point coarse-fine stencil, over a region whose surface crosses the coarse-fine interface;
//  - a manufactured Poisson solution converges at second order with refined boxes straddling it
//    (ratios 2 and 4, two and three levels), and CG + BoomerAMG needs about as many iterations on each grid;
//  - 1 rank and all ranks give the same solution to solver tolerance.
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "fluid/composite_poisson.hpp"
#include "io/petsc_check.hpp"

namespace ibvalve::fluid {
namespace {

// u = sin(2x + 1) cos(3y) e^z has -lap u = (4 + 9 - 1) u.
double exact(const Real3& x)
{
  return std::sin(2.0 * x[0] + 1.0) * std::cos(3.0 * x[1]) * std::exp(x[2]);
}
double source(const Real3& x)
{
  return 12.0 * exact(x);
}

BoxGeometry unit_box(PetscInt n)
{
  BoxGeometry b;
  b.cells = {n, n, n};
  b.periodic = {false, false, false};
  return b;
}

// A box given in units of 1/8 of the unit cube, as cells of a level with n0 * ratio cells per side.
IndexBox eighths(const Index3& lo, const Index3& hi, PetscInt cells_per_side)
{
  IndexBox b;
  for (int d = 0; d < 3; ++d) {
    b.lower[d] = lo[d] * cells_per_side / 8;
    b.upper[d] = hi[d] * cells_per_side / 8;
  }
  return b;
}

enum class Layout { two_levels_ratio2, two_levels_ratio4, three_levels, l_shaped };

GridHierarchy make_hierarchy(PetscInt n0, Layout layout)
{
  // Level 1 straddles the middle of the cube off-centre: [2/8, 5/8] x [3/8, 6/8] x [2/8, 4/8].
  if (layout == Layout::l_shaped) {
    // Two adjacent boxes (fine-fine faces between boxes), an L-shaped union with a concave corner (one-sided
    // tangential slopes there), the second box reaching the domain side x = 1 (fine Dirichlet faces).
    return GridHierarchy(
        unit_box(n0),
        {FinerLevel{2, {eighths({2, 3, 2}, {5, 6, 4}, n0 * 2), eighths({5, 3, 2}, {8, 5, 4}, n0 * 2)}}});
  }
  const PetscInt r1 = layout == Layout::two_levels_ratio4 ? 4 : 2;
  std::vector<FinerLevel> finer{FinerLevel{r1, {eighths({2, 3, 2}, {5, 6, 4}, n0 * r1)}}};
  if (layout == Layout::three_levels) {
    // Level 2 (ratio 2): level 1 shrunk by 1/16 of the cube on every side (n0/4 level-2 cells).
    finer.push_back(FinerLevel{2, {eighths({2, 3, 2}, {5, 6, 4}, n0 * 4).grown(-n0 / 4)}});
  }
  return GridHierarchy(unit_box(n0), finer);
}

// Figures are printed by rank 0 only.
template <class... Args>
void report(const char* format, Args... args)
{
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0) std::printf(format, args...);
}

double norm(Vec v, NormType type)
{
  double n = 0.0;
  PETSC_CHECK(VecNorm(v, type, &n));
  return n;
}

TEST(CompositeOperators, PressureOperatorIsSymmetric)
{
  for (const auto stencil : {CoarseFineStencil::two_point, CoarseFineStencil::tangential_linear})
    for (const auto boundary : {CompositeBoundary::dirichlet, CompositeBoundary::neumann}) {
      for (const auto layout : {Layout::three_levels, Layout::l_shaped}) {
        const GridHierarchy h = make_hierarchy(16, layout);
        const CompositeOperators ops(PETSC_COMM_WORLD, h, stencil, boundary, exact);
        const petsc::OwnedVec x = ops.create_cell_vector(), y = ops.create_cell_vector(),
                              ax = ops.create_cell_vector(), ay = ops.create_cell_vector();
        petsc::OwnedPetscRandom random;
        PETSC_CHECK(PetscRandomCreate(PETSC_COMM_WORLD, random.out()));
        PETSC_CHECK(PetscRandomSetInterval(random, -1.0, 1.0));
        PETSC_CHECK(VecSetRandom(x, random));
        PETSC_CHECK(VecSetRandom(y, random));
        PETSC_CHECK(MatMult(ops.laplacian(), x, ax));
        PETSC_CHECK(MatMult(ops.laplacian(), y, ay));
        double x_ay = 0.0, y_ax = 0.0, a_norm = 0.0;
        PETSC_CHECK(VecDot(x, ay, &x_ay));
        PETSC_CHECK(VecDot(y, ax, &y_ax));
        PETSC_CHECK(MatNorm(ops.laplacian(), NORM_FROBENIUS, &a_norm));
        const double bound = 1e-12 * norm(x, NORM_2) * a_norm * norm(y, NORM_2);
        EXPECT_LE(std::abs(x_ay - y_ax), bound);
        report("symmetry (%s, %s): |x.Ay - y.Ax| = %.2e, 1e-12 |x||A||y| = %.2e, %d composite cells\n",
               stencil == CoarseFineStencil::two_point ? "two-point" : "tangential",
               boundary == CompositeBoundary::dirichlet ? "Dirichlet" : "Neumann", std::abs(x_ay - y_ax),
               bound, static_cast<int>(ops.cells().size()));
        // Positive definite with Dirichlet sides; constants are the null space with Neumann sides.
        double x_ax = 0.0;
        PETSC_CHECK(VecDot(x, ax, &x_ax));
        EXPECT_GT(x_ax, 0.0);
        if (boundary == CompositeBoundary::neumann) {
          PETSC_CHECK(VecSet(x, 1.0));
          PETSC_CHECK(MatMult(ops.laplacian(), x, ax));
          EXPECT_LE(norm(ax, NORM_INFINITY), 1e-12 * a_norm);
        }
      }
    }
}

// Sum over this rank's faces of `weight(face) * g_f` (reduced over ranks).
template <class Select>
double face_sum(const CompositeOperators& ops, Vec g, Select weight)
{
  const PetscScalar* a = nullptr;
  PETSC_CHECK(VecGetArrayRead(g, &a));
  double sum = 0.0;
  for (std::size_t f = 0; f < ops.owned_faces().size(); ++f) sum += weight(ops.owned_faces()[f]) * a[f];
  PETSC_CHECK(VecRestoreArrayRead(g, &a));
  double total = 0.0;
  MPI_Allreduce(&sum, &total, 1, MPI_DOUBLE, MPI_SUM, ops.comm());
  return total;
}

// Sum of V D g over the composite cells whose centre satisfies `inside`.
template <class Inside>
double cell_sum(const CompositeOperators& ops, Vec div, Inside inside)
{
  PetscInt begin = 0, end = 0;
  PETSC_CHECK(VecGetOwnershipRange(div, &begin, &end));
  const PetscScalar* a = nullptr;
  PETSC_CHECK(VecGetArrayRead(div, &a));
  double sum = 0.0;
  ops.cells().for_each(begin, end, [&](PetscInt n, const CompositeCells::Cell& c) {
    const GridHierarchy& h = ops.cells().hierarchy();
    if (inside(h.cell_center(c.level, c.index))) sum += h.cell_volume(c.level) * a[n - begin];
  });
  PETSC_CHECK(VecRestoreArrayRead(div, &a));
  double total = 0.0;
  MPI_Allreduce(&sum, &total, 1, MPI_DOUBLE, MPI_SUM, ops.comm());
  return total;
}

TEST(CompositeOperators, DivergenceIsConservativeAcrossCoarseFineFaces)
{
  for (const auto stencil : {CoarseFineStencil::two_point, CoarseFineStencil::tangential_linear}) {
    for (const auto layout : {Layout::three_levels, Layout::l_shaped}) {
      const GridHierarchy h = make_hierarchy(16, layout);
      const CompositeOperators ops(PETSC_COMM_WORLD, h, stencil, CompositeBoundary::dirichlet, exact);
      const petsc::OwnedVec g = ops.create_face_vector(), div = ops.create_cell_vector();
      petsc::OwnedPetscRandom random;
      PETSC_CHECK(PetscRandomCreate(PETSC_COMM_WORLD, random.out()));
      PETSC_CHECK(VecSetRandom(g, random));
      ops.divergence(g, div);
      // Whole box: sum of V D g = net outflow through the box's sides.
      const double inside_all = cell_sum(ops, div, [](const Real3&) { return true; });
      const double outflow =
          face_sum(ops, g, [](const CompositeFace& f) { return f.on_boundary ? f.outward * f.area : 0.0; });
      const double scale = face_sum(ops, g, [](const CompositeFace& f) { return f.area; });
      EXPECT_NEAR(inside_all, outflow, 1e-13 * scale);
      // The half x < 1/2: its surface crosses the coarse-fine interfaces of both finer levels.
      const double half = cell_sum(ops, div, [](const Real3& x) { return x[0] < 0.5; });
      const double half_outflow = face_sum(ops, g, [](const CompositeFace& f) {
        if (f.on_boundary && f.center[0] < 0.5) return f.outward * f.area;
        if (!f.on_boundary && f.normal == 0 && std::abs(f.center[0] - 0.5) < 1e-12) return f.area;
        return 0.0;
      });
      if (stencil == CoarseFineStencil::two_point) {
        EXPECT_NEAR(half, half_outflow, 1e-13 * scale);
      }
      report("conservation (%s): box %.3e vs outflow %.3e; half box %.3e vs outflow %.3e\n",
             stencil == CoarseFineStencil::two_point ? "two-point" : "tangential", inside_all, outflow, half,
             half_outflow);
    }
  }
}

struct Result {
  double l2 = 0.0, max = 0.0;
  double finest_max = 0.0; // max error on the finest level alone (its cells touch the interface)
  PetscInt iterations = 0, cells = 0;
};

Result solve_manufactured(MPI_Comm comm, PetscInt n0, Layout layout, CoarseFineStencil stencil,
                          std::vector<double>* gathered = nullptr)
{
  const GridHierarchy h = make_hierarchy(n0, layout);
  const CompositeOperators ops(comm, h, stencil, CompositeBoundary::dirichlet, exact);
  const CompositePoissonSolver solver(ops, false, "nested_test_", 1e-11);
  const petsc::OwnedVec b = ops.create_cell_vector(), u = ops.create_cell_vector(),
                        e = ops.create_cell_vector();
  ops.right_side(source, b);
  Result r;
  r.iterations = solver.solve(b, u);
  r.cells = ops.cells().size();
  ops.sample(exact, e);
  PETSC_CHECK(VecAXPY(e, -1.0, u));
  r.max = norm(e, NORM_INFINITY);
  {
    PetscInt begin = 0, end = 0;
    PETSC_CHECK(VecGetOwnershipRange(e, &begin, &end));
    const PetscScalar* a = nullptr;
    PETSC_CHECK(VecGetArrayRead(e, &a));
    double m = 0.0;
    ops.cells().for_each(begin, end, [&](PetscInt n, const CompositeCells::Cell& c) {
      if (c.level == h.finest()) m = std::max(m, std::abs(a[n - begin]));
    });
    PETSC_CHECK(VecRestoreArrayRead(e, &a));
    MPI_Allreduce(&m, &r.finest_max, 1, MPI_DOUBLE, MPI_MAX, comm);
  }
  PETSC_CHECK(VecPointwiseMult(b, e, e));
  double weighted = 0.0;
  PETSC_CHECK(VecDot(b, ops.volumes(), &weighted));
  r.l2 = std::sqrt(weighted); // the unit cube has volume 1
  if (gathered) {
    petsc::OwnedVecScatter scatter;
    petsc::OwnedVec all;
    PETSC_CHECK(VecScatterCreateToAll(u, scatter.out(), all.out()));
    PETSC_CHECK(VecScatterBegin(scatter, u, all, INSERT_VALUES, SCATTER_FORWARD));
    PETSC_CHECK(VecScatterEnd(scatter, u, all, INSERT_VALUES, SCATTER_FORWARD));
    const PetscScalar* a = nullptr;
    PETSC_CHECK(VecGetArrayRead(all, &a));
    gathered->assign(a, a + r.cells);
    PETSC_CHECK(VecRestoreArrayRead(all, &a));
  }
  return r;
}

void expect_second_order(Layout layout, CoarseFineStencil stencil, const char* name, double min_l2_order,
                         double min_max_order)
{
  std::vector<Result> results;
  for (const PetscInt n0 : {8, 16, 32})
    results.push_back(solve_manufactured(PETSC_COMM_WORLD, n0, layout, stencil));
  for (std::size_t i = 0; i < results.size(); ++i) {
    const Result& r = results[i];
    report("%s: N0 = %d, %d cells, L2 %.3e, max %.3e (finest level %.3e), CG+BoomerAMG %d iterations", name,
           8 << i, static_cast<int>(r.cells), r.l2, r.max, r.finest_max, static_cast<int>(r.iterations));
    if (i > 0)
      report(", orders L2 %.2f max %.2f finest %.2f", std::log2(results[i - 1].l2 / r.l2),
             std::log2(results[i - 1].max / r.max), std::log2(results[i - 1].finest_max / r.finest_max));
    report("\n");
  }
  EXPECT_GE(std::log2(results[1].l2 / results[2].l2), min_l2_order) << name;
  EXPECT_GE(std::log2(results[1].max / results[2].max), min_max_order) << name;
  // The finest level alone, whose cells line the coarse-fine interface (measured 1.87 to 1.91).
  EXPECT_GE(std::log2(results[1].finest_max / results[2].finest_max), min_max_order) << name;
  // Multigrid: the iteration count barely grows with the resolution.
  EXPECT_LE(results[2].iterations, results[0].iterations + 6) << name;
}

TEST(CompositePoisson, ManufacturedSolutionConvergesAtSecondOrder)
{
  // Measured on 8/16/32: L2 orders 1.97, 1.99; max-norm orders 1.76, 1.86 over all levels and 1.66-1.72,
  // 1.87-1.91 on the finest level alone (the coarse-fine flux error is O(h) on a layer of faces).
  expect_second_order(Layout::two_levels_ratio2, CoarseFineStencil::tangential_linear, "ratio 2, tangential",
                      1.9, 1.75);
  expect_second_order(Layout::two_levels_ratio4, CoarseFineStencil::tangential_linear, "ratio 4, tangential",
                      1.9, 1.75);
  expect_second_order(Layout::three_levels, CoarseFineStencil::tangential_linear, "3 levels, tangential", 1.9,
                      1.75);
  expect_second_order(Layout::l_shaped, CoarseFineStencil::tangential_linear, "L-shaped, tangential", 1.9,
                      1.75);
}

TEST(CompositePoisson, TwoPointCoarseFineFluxIsOnlyFirstOrderInMaxNorm)
{
  // The two-point flux is inconsistent at hanging faces (an O(1) flux error alternating along the face), so
  // the max-norm error near the interface only falls like h: this is why the tangential term is the default.
  std::vector<Result> r;
  for (const PetscInt n0 : {8, 16, 32})
    r.push_back(
        solve_manufactured(PETSC_COMM_WORLD, n0, Layout::two_levels_ratio2, CoarseFineStencil::two_point));
  const double max_order = std::log2(r[1].max / r[2].max);
  report("ratio 2, two-point: max errors %.3e %.3e %.3e (order %.2f), L2 %.3e %.3e %.3e (order %.2f)\n",
         r[0].max, r[1].max, r[2].max, max_order, r[0].l2, r[1].l2, r[2].l2, std::log2(r[1].l2 / r[2].l2));
  EXPECT_GT(max_order, 0.7);
  EXPECT_LT(max_order, 1.2);
}

TEST(CompositeOperators, RefusePeriodicSidesAndMissingBoundaryValues)
{
  BoxGeometry periodic;
  periodic.cells = {8, 8, 8};
  periodic.periodic = {false, true, false};
  EXPECT_THROW(CompositeOperators(PETSC_COMM_WORLD, GridHierarchy(periodic, {}),
                                  CoarseFineStencil::tangential_linear, CompositeBoundary::neumann),
               std::invalid_argument);
  EXPECT_THROW(CompositeOperators(PETSC_COMM_WORLD, make_hierarchy(8, Layout::two_levels_ratio2),
                                  CoarseFineStencil::tangential_linear, CompositeBoundary::dirichlet),
               std::invalid_argument);
}

TEST(CompositePoisson, OneRankAndAllRanksAgree)
{
  std::vector<double> mine, alone;
  solve_manufactured(PETSC_COMM_WORLD, 16, Layout::three_levels, CoarseFineStencil::tangential_linear, &mine);
  solve_manufactured(PETSC_COMM_SELF, 16, Layout::three_levels, CoarseFineStencil::tangential_linear, &alone);
  ASSERT_EQ(mine.size(), alone.size());
  double difference = 0.0, size = 0.0;
  for (std::size_t i = 0; i < mine.size(); ++i) {
    difference = std::max(difference, std::abs(mine[i] - alone[i]));
    size = std::max(size, std::abs(alone[i]));
  }
  report("1 rank vs all ranks: max difference %.2e (max |u| %.2f)\n", difference, size);
  EXPECT_LE(difference, 1e-8 * size);
}

} // namespace
} // namespace ibvalve::fluid
