#include "ib/interaction.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include <mpi.h>
#include <petscdmda.h>
#include <petscdmstag.h>

#include "base/errors.hpp"
#include "io/petsc_check.hpp"
#include "io/petsc_handle.hpp"

namespace ibvalve::ib {

namespace {

/// The first grid index and the weights per direction of velocity component d at a prepared point:
/// component d sits on the faces normal to d, so along d the face set (0), across it the cell-centre
/// set (1) of the point's 6 support weights.
std::pair<std::array<int, 3>, std::array<const double*, 3>>
component_stencil(const std::array<int, 6>& first, const double* weights, int support, int d)
{
  std::array<int, 3> f{};
  std::array<const double*, 3> w{};
  for (int e = 0; e < 3; ++e) {
    const int set = e == d ? 0 : 1;
    f[e] = first[static_cast<std::size_t>(3 * set + e)];
    w[e] = weights + (3 * set + e) * support;
  }
  return {f, w};
}

/// Sum over the S^3 grid values from `base` (x contiguous, y rows `sy` apart, z planes `sz`) weighted
/// by w0[m] w1[j] w2[k]: the interpolation of one velocity component at an interior point, with the
/// kernel's support known at compile time. The S^2 rows are summed first as S running sums along x
/// (one vector operation per row), then weighted by w0.
template <int S>
double weighted_sum(const PetscScalar* base, PetscInt sy, PetscInt sz, const double* w0, const double* w1,
                    const double* w2)
{
  double along_x[S] = {};
  for (int k = 0; k < S; ++k)
    for (int j = 0; j < S; ++j) {
      const PetscScalar* row = base + k * sz + j * sy;
      const double wjk = w2[k] * w1[j];
      for (int m = 0; m < S; ++m) along_x[m] += wjk * row[m];
    }
  double sum = 0.0;
  for (int m = 0; m < S; ++m) sum += w0[m] * along_x[m];
  return sum;
}

/// Calls visit(i, j, k) for every face of component d this rank owns, in the order of that component's
/// global vector (x fastest, then y, then z): the one order in which gather_velocity fills the vector
/// and scatter_force reads it back.
template <class Visit>
void for_each_owned_face(const fluid::StaggeredGrid& grid, int d, Visit&& visit)
{
  for (PetscInt k = grid.begin(2); k < grid.face_end(d, 2); ++k)
    for (PetscInt j = grid.begin(1); j < grid.face_end(d, 1); ++j)
      for (PetscInt i = grid.begin(0); i < grid.face_end(d, 0); ++i) visit(i, j, k);
}

/// The adjoint of weighted_sum: adds F w0[m] w1[j] w2[k] to the S^3 grid values from `base`.
template <int S>
void weighted_add(PetscScalar* base, PetscInt sy, PetscInt sz, const double* w0, const double* w1,
                  const double* w2, double F)
{
  double Fw0[S];
  for (int m = 0; m < S; ++m) Fw0[m] = F * w0[m];
  for (int k = 0; k < S; ++k)
    for (int j = 0; j < S; ++j) {
      PetscScalar* row = base + k * sz + j * sy;
      const double wjk = w2[k] * w1[j];
      for (int m = 0; m < S; ++m) row[m] += wjk * Fw0[m];
    }
}

} // namespace

GridInteraction::GridInteraction(const fluid::StaggeredGrid& grid, KernelKind kernel)
    : grid_(grid), kernel_(kernel)
{
  for (int d = 0; d < 3; ++d)
    if (grid.count(d) < kernel_.ghost_width())
      throw std::invalid_argument(
          fmt::format("ib: each rank needs at least {} cells per direction for the {} kernel",
                      kernel_.ghost_width(), kernel_.name()));
  PetscInt ranks[3];
  PETSC_CHECK(DMStagGetNumRanks(grid.dm(), &ranks[0], &ranks[1], &ranks[2]));
  const PetscInt* cell_ranges[3] = {nullptr, nullptr, nullptr};
  PETSC_CHECK(DMStagGetOwnershipRanges(grid.dm(), &cell_ranges[0], &cell_ranges[1], &cell_ranges[2]));
  auto boundary = [&](int e) { return grid.periodic(e) ? DM_BOUNDARY_PERIODIC : DM_BOUNDARY_GHOSTED; };
  for (int d = 0; d < 3; ++d) {
    // The faces normal to d: along d one more than the cells in a walled box, the extra (upper) face
    // owned by the last rank, as in the fluid grid; across d the cells' layout.
    std::array<PetscInt, 3> points{};
    std::array<std::vector<PetscInt>, 3> ranges;
    for (int e = 0; e < 3; ++e) {
      const bool extra = e == d && !grid.periodic(e);
      points[e] = grid.cells(e) + (extra ? 1 : 0);
      ranges[e].assign(cell_ranges[e], cell_ranges[e] + ranks[e]);
      if (extra) ++ranges[e].back();
    }
    const auto c = static_cast<std::size_t>(d);
    PETSC_CHECK(DMDACreate3d(grid.comm(), boundary(0), boundary(1), boundary(2), DMDA_STENCIL_BOX, points[0],
                             points[1], points[2], ranks[0], ranks[1], ranks[2], 1, kernel_.ghost_width(),
                             ranges[0].data(), ranges[1].data(), ranges[2].data(), dm_[c].out()));
    PETSC_CHECK(DMSetUp(dm_[c]));
    PETSC_CHECK(DMCreateGlobalVector(dm_[c], global_[c].out()));
    PETSC_CHECK(DMCreateLocalVector(dm_[c], local_[c].out()));
    PetscInt start[3], count[3], ghost_count[3];
    PETSC_CHECK(DMDAGetCorners(dm_[c], &start[0], &start[1], &start[2], &count[0], &count[1], &count[2]));
    for (int e = 0; e < 3; ++e)
      if (start[e] != grid.begin(e) || start[e] + count[e] != grid.face_end(d, e))
        throw std::logic_error("ib: the interaction's faces are not owned as the fluid grid's");
    PETSC_CHECK(DMDAGetGhostCorners(dm_[c], &ghost_start_[c][0], &ghost_start_[c][1], &ghost_start_[c][2],
                                    &ghost_count[0], &ghost_count[1], &ghost_count[2]));
    row_stride_[c] = ghost_count[0];
    plane_stride_[c] = ghost_count[0] * ghost_count[1];
  }
}

Vec3 GridInteraction::wrap(const Vec3& x) const
{
  const fluid::BoxGeometry& box = grid_.box();
  Vec3 y = x;
  for (int d = 0; d < 3; ++d) {
    if (!std::isfinite(x[d])) {
      std::ostringstream msg;
      msg << "ib: a structure point has a non-finite position (" << x.transpose() << "): the run diverged";
      throw RunError(msg.str());
    }
    if (grid_.periodic(d)) {
      const double L = box.length(d);
      y[d] = box.lower[d] + (x[d] - box.lower[d]) - L * std::floor((x[d] - box.lower[d]) / L);
    } else if (x[d] < box.lower[d] || x[d] > box.upper[d]) {
      std::ostringstream msg;
      msg << "ib: structure point (" << x.transpose() << ") left the grid: direction "
          << "xyz"[d] << " spans [" << box.lower[d] << ", " << box.upper[d] << "]";
      throw RunError(msg.str());
    }
  }
  return y;
}

bool GridInteraction::owns(const Vec3& x) const
{
  return owns_wrapped(wrap(x));
}

bool GridInteraction::owns_wrapped(const Vec3& y) const
{
  for (int d = 0; d < 3; ++d)
    if (!owns_cell(d, cell_of(d, grid_coordinate(d, y[d])))) return false;
  return true;
}

std::pair<int, int> GridInteraction::valid_range(int component, int e, int first) const
{
  const int support = kernel_.support();
  if (grid_.periodic(e)) return {0, support};
  const PetscInt last = component == e ? grid_.cells(e) : grid_.cells(e) - 1;
  const int lo = static_cast<int>(std::max<PetscInt>(0, -first));
  const int hi = static_cast<int>(std::min<PetscInt>(support, last - first + 1));
  return {lo, std::max(lo, hi)};
}

void GridInteraction::prepare(std::span<const Vec3> points, PreparedPoints& prepared) const
{
  start_preparing(points.size(), prepared);
  for (std::size_t p = 0; p < points.size(); ++p) prepare_point(points[p], p, prepared);
}

void GridInteraction::prepare(std::span<const Vec3> points, std::span<const std::size_t> candidates,
                              PreparedPoints& prepared) const
{
  start_preparing(candidates.size(), prepared);
  for (const std::size_t p : candidates) prepare_point(points[p], p, prepared);
}

void GridInteraction::start_preparing(std::size_t at_most, PreparedPoints& prepared) const
{
  prepared.index.clear();
  prepared.first.clear();
  prepared.inside.clear();
  // The kernel writes each point's weights in place: room for every candidate, grown (zeroed) only
  // when a placement has more than any before it.
  const std::size_t needed = at_most * 6 * static_cast<std::size_t>(kernel_.support());
  if (prepared.weights.size() < needed) prepared.weights.resize(needed);
}

bool GridInteraction::may_hold(const Vec3& lower, const Vec3& upper) const
{
  const fluid::BoxGeometry& box = grid_.box();
  for (int d = 0; d < 3; ++d) {
    if (grid_.periodic(d)) continue;
    if (!(lower[d] >= box.lower[d] && upper[d] <= box.upper[d])) return true; // outside, or not finite
    // Widened by a millionth of a cell: a point summed from the nodes may round just past them.
    const double margin = 1e-6 * grid_.h(d);
    const PetscInt first = cell_of(d, grid_coordinate(d, lower[d] - margin));
    const PetscInt last = cell_of(d, grid_coordinate(d, upper[d] + margin));
    if (last < grid_.begin(d) || first >= grid_.begin(d) + grid_.count(d)) return false;
  }
  return true;
}

void GridInteraction::prepare_point(const Vec3& x, std::size_t p, PreparedPoints& prepared) const
{
  const int S = kernel_.support();
  const Vec3 y = wrap(x);
  // The point's grid coordinate per direction, computed once for the ownership test (owns_wrapped's)
  // and both stencils.
  std::array<double, 3> s{};
  bool mine = true;
  for (int d = 0; d < 3 && mine; ++d) {
    s[static_cast<std::size_t>(d)] = grid_coordinate(d, y[d]);
    mine = owns_cell(d, cell_of(d, s[static_cast<std::size_t>(d)]));
  }
  if (!mine) return;
  double* weights = prepared.weights.data() + prepared.index.size() * 6 * static_cast<std::size_t>(S);
  prepared.index.push_back(p);
  std::array<int, 6> first{};
  for (int set = 0; set < 2; ++set) // faces normal to e sit at t = i, cell centres at t = i + 1/2
    for (int e = 0; e < 3; ++e, weights += S) {
      const double t = s[static_cast<std::size_t>(e)] - (set == 1 ? 0.5 : 0.0);
      first[static_cast<std::size_t>(3 * set + e)] = kernel_.weights(t, weights);
    }
  std::uint8_t inside = 0;
  for (int d = 0; d < 3; ++d) {
    bool all = true;
    for (int e = 0; e < 3; ++e) {
      const auto [lo, hi] = valid_range(d, e, first[static_cast<std::size_t>(e == d ? e : 3 + e)]);
      all = all && lo == 0 && hi == S;
    }
    if (all) inside = static_cast<std::uint8_t>(inside | (1u << d));
  }
  prepared.first.push_back(first);
  prepared.inside.push_back(inside);
}

void GridInteraction::gather_velocity(Vec velocity)
{
  {
    fluid::StagArray u(grid_, velocity, true);
    for (int d = 0; d < 3; ++d) {
      petsc::VecArray owned(global_[static_cast<std::size_t>(d)]);
      PetscScalar* g = owned.data();
      const PetscInt slot = grid_.face_slot(d);
      for_each_owned_face(grid_, d, [&](PetscInt i, PetscInt j, PetscInt k) { *g++ = u(i, j, k, slot); });
    }
  }
  for (std::size_t c = 0; c < 3; ++c)
    PETSC_CHECK(DMGlobalToLocalBegin(dm_[c], global_[c], INSERT_VALUES, local_[c]));
  for (std::size_t c = 0; c < 3; ++c)
    PETSC_CHECK(DMGlobalToLocalEnd(dm_[c], global_[c], INSERT_VALUES, local_[c]));
}

void GridInteraction::interpolate(Vec velocity, const PreparedPoints& points, std::span<Vec3> values)
{
  gather_velocity(velocity);
  const petsc::VecArray ux(local_[0]), uy(local_[1]), uz(local_[2]);
  const std::array<const PetscScalar*, 3> u{ux.data(), uy.data(), uz.data()};
  const int S = kernel_.support();
  for (std::size_t p = 0; p < points.size(); ++p) {
    const std::array<int, 6>& first = points.first[p];
    const double* weights = points.weights.data() + 6 * S * p;
    for (int d = 0; d < 3; ++d) {
      const auto c = static_cast<std::size_t>(d);
      const auto [f, w] = component_stencil(first, weights, S, d);
      double sum = 0.0;
      if (S == 4 && (points.inside[p] >> d & 1u)) { // the whole stencil inside the box: unrolled loops
        sum = weighted_sum<4>(u[c] + offset(d, f[0], f[1], f[2]), row_stride_[c], plane_stride_[c], w[0],
                              w[1], w[2]);
      } else {
        const auto [a0, b0] = valid_range(d, 0, f[0]);
        const auto [a1, b1] = valid_range(d, 1, f[1]);
        const auto [a2, b2] = valid_range(d, 2, f[2]);
        if (a0 < b0) // else the whole stencil lies outside a walled box (the point is on a wall)
          for (int k = a2; k < b2; ++k)
            for (int j = a1; j < b1; ++j) {
              double row = 0.0;
              const PetscScalar* entry = u[c] + offset(d, f[0] + a0, f[1] + j, f[2] + k);
              for (int m = a0; m < b0; ++m, ++entry) row += w[0][m] * *entry;
              sum += w[2][k] * w[1][j] * row;
            }
      }
      values[p][d] = sum;
    }
  }
}

void GridInteraction::interpolate(Vec velocity, std::span<const Vec3> points, std::span<Vec3> values)
{
  PreparedPoints prepared;
  prepare(points, prepared);
  std::vector<Vec3> owned(prepared.size());
  interpolate(velocity, prepared, owned);
  for (Vec3& v : values) v.setZero();
  for (std::size_t i = 0; i < prepared.size(); ++i) values[prepared.index[i]] = owned[i];
}

void GridInteraction::spread(const PreparedPoints& points, std::span<const Vec3> forces, Vec force, bool add)
{
  for (const petsc::OwnedVec& local : local_) PETSC_CHECK(VecZeroEntries(local));
  const double inverse_volume = 1.0 / grid_.cell_volume();
  const int S = kernel_.support();
  {
    const petsc::VecArray fx(local_[0]), fy(local_[1]), fz(local_[2]);
    const std::array<PetscScalar*, 3> a{fx.data(), fy.data(), fz.data()};
    for (std::size_t p = 0; p < points.size(); ++p) {
      const std::array<int, 6>& first = points.first[p];
      const double* weights = points.weights.data() + 6 * S * p;
      for (int d = 0; d < 3; ++d) {
        const auto c = static_cast<std::size_t>(d);
        const double F = forces[p][d] * inverse_volume;
        if (F == 0.0) continue;
        const auto [f, w] = component_stencil(first, weights, S, d);
        if (S == 4 && (points.inside[p] >> d & 1u)) {
          weighted_add<4>(a[c] + offset(d, f[0], f[1], f[2]), row_stride_[c], plane_stride_[c], w[0], w[1],
                          w[2], F);
          continue;
        }
        const auto [a0, b0] = valid_range(d, 0, f[0]);
        const auto [a1, b1] = valid_range(d, 1, f[1]);
        const auto [a2, b2] = valid_range(d, 2, f[2]);
        if (a0 >= b0) continue;
        for (int k = a2; k < b2; ++k)
          for (int j = a1; j < b1; ++j) {
            const double wjk = F * w[2][k] * w[1][j];
            PetscScalar* entry = a[c] + offset(d, f[0] + a0, f[1] + j, f[2] + k);
            for (int m = a0; m < b0; ++m, ++entry) *entry += wjk * w[0][m];
          }
      }
    }
  }
  scatter_force(force, add);
}

void GridInteraction::spread(std::span<const Vec3> points, std::span<const Vec3> forces, Vec force, bool add)
{
  PreparedPoints prepared;
  prepare(points, prepared);
  std::vector<Vec3> owned(prepared.size());
  for (std::size_t i = 0; i < prepared.size(); ++i) owned[i] = forces[prepared.index[i]];
  spread(prepared, owned, force, add);
}

void GridInteraction::scatter_force(Vec force, bool add)
{
  // Ghost contributions (other ranks' faces, periodic images) go to their owners.
  for (std::size_t c = 0; c < 3; ++c) {
    PETSC_CHECK(VecZeroEntries(global_[c]));
    PETSC_CHECK(DMLocalToGlobalBegin(dm_[c], local_[c], ADD_VALUES, global_[c]));
  }
  for (std::size_t c = 0; c < 3; ++c)
    PETSC_CHECK(DMLocalToGlobalEnd(dm_[c], local_[c], ADD_VALUES, global_[c]));
  fluid::StagArray f(grid_, force);
  for (int d = 0; d < 3; ++d) {
    const petsc::VecArray owned(global_[static_cast<std::size_t>(d)]);
    const PetscScalar* g = owned.data();
    const PetscInt slot = grid_.face_slot(d);
    for_each_owned_face(grid_, d, [&](PetscInt i, PetscInt j, PetscInt k) {
      PetscScalar& target = f(i, j, k, slot);
      target = (add ? target : 0.0) + *g++;
    });
  }
}

double GridInteraction::inner_product(Vec va, Vec vb) const
{
  fluid::StagArray a(grid_, va, true), b(grid_, vb, true);
  double sum = 0.0;
  for (int d = 0; d < 3; ++d) {
    const PetscInt slot = grid_.face_slot(d);
    for_each_owned_face(
        grid_, d, [&](PetscInt i, PetscInt j, PetscInt k) { sum += a(i, j, k, slot) * b(i, j, k, slot); });
  }
  double total = 0.0;
  MPI_Allreduce(&sum, &total, 1, MPI_DOUBLE, MPI_SUM, grid_.comm());
  return total * grid_.cell_volume();
}

} // namespace ibvalve::ib
