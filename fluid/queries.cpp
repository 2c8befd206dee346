#include "fluid/queries.hpp"

#include <algorithm>
#include <cmath>

namespace ibvalve::fluid {

namespace {

double sum_all(const StaggeredGrid& grid, double x)
{
  MPI_Allreduce(MPI_IN_PLACE, &x, 1, MPI_DOUBLE, MPI_SUM, grid.comm());
  return x;
}

double max_all(const StaggeredGrid& grid, double x)
{
  MPI_Allreduce(MPI_IN_PLACE, &x, 1, MPI_DOUBLE, MPI_MAX, grid.comm());
  return x;
}

/// Quadrature weight of a face: half a cell on a non-periodic boundary, a whole cell elsewhere.
double face_weight(const StaggeredGrid& grid, int d, PetscInt index)
{
  return grid.is_boundary_face(d, index) ? 0.5 : 1.0;
}

template <class F>
void for_owned_cells(const StaggeredGrid& grid, F&& f)
{
  for (PetscInt k = grid.begin(2); k < grid.begin(2) + grid.count(2); ++k)
    for (PetscInt j = grid.begin(1); j < grid.begin(1) + grid.count(1); ++j)
      for (PetscInt i = grid.begin(0); i < grid.begin(0) + grid.count(0); ++i) f(i, j, k);
}

template <class F>
void for_owned_faces(const StaggeredGrid& grid, int d, F&& f)
{
  for (PetscInt k = grid.begin(2); k < grid.face_end(d, 2); ++k)
    for (PetscInt j = grid.begin(1); j < grid.face_end(d, 1); ++j)
      for (PetscInt i = grid.begin(0); i < grid.face_end(d, 0); ++i) f(i, j, k);
}

/// The cell-centred vorticity component a of cell (i,j,k): the average of its four edges along a.
double cell_vorticity(const StaggeredGrid& grid, const StagArray& u, int a, PetscInt i, PetscInt j,
                      PetscInt k)
{
  const int b = (a + 1) % 3, c = (a + 2) % 3;
  const PetscInt sb = grid.face_slot(b), sc = grid.face_slot(c);
  double sum = 0.0;
  for (int db = 0; db < 2; ++db)
    for (int dc = 0; dc < 2; ++dc) {
      Index3 e{i, j, k};
      e[b] += db;
      e[c] += dc;
      Index3 eb = e, ec = e;
      eb[b] -= 1;
      ec[c] -= 1;
      // omega_a = d u_c / d x_b - d u_b / d x_c on the edge at e.
      sum += (u(e[0], e[1], e[2], sc) - u(eb[0], eb[1], eb[2], sc)) / grid.h(b) -
             (u(e[0], e[1], e[2], sb) - u(ec[0], ec[1], ec[2], sb)) / grid.h(c);
    }
  return 0.25 * sum;
}

/// Trilinear interpolation of the quantity in `slot`, whose samples sit at lower + (i + offset) h.
double interpolate(const StaggeredGrid& grid, Vec state, PetscInt slot, const Real3& offset, const Real3& x)
{
  Index3 cell{};
  for (int e = 0; e < 3; ++e) {
    const auto c = static_cast<PetscInt>(std::floor((x[e] - grid.box().lower[e]) / grid.h(e)));
    cell[e] = std::clamp<PetscInt>(c, 0, grid.cells(e) - 1);
    if (cell[e] < grid.begin(e) || cell[e] >= grid.begin(e) + grid.count(e)) return 0.0; // not this rank's
  }
  StagArray a(grid, state, true);
  Index3 base{};
  double w[3];
  for (int e = 0; e < 3; ++e) {
    const double s = (x[e] - grid.box().lower[e]) / grid.h(e) - offset[e];
    base[e] = static_cast<PetscInt>(std::floor(s));
    w[e] = s - static_cast<double>(base[e]);
  }
  double value = 0.0;
  for (int dk = 0; dk < 2; ++dk)
    for (int dj = 0; dj < 2; ++dj)
      for (int di = 0; di < 2; ++di) {
        const double weight = (di ? w[0] : 1.0 - w[0]) * (dj ? w[1] : 1.0 - w[1]) * (dk ? w[2] : 1.0 - w[2]);
        value += weight * a(base[0] + di, base[1] + dj, base[2] + dk, slot);
      }
  return value;
}

} // namespace

PlaneRegion PlaneRegion::disk(int normal, double position, Real3 center, double radius)
{
  PlaneRegion r;
  r.normal = normal;
  r.position = position;
  r.shape = Shape::disk;
  r.center = center;
  r.radius = radius;
  return r;
}

PlaneRegion PlaneRegion::rectangle(int normal, double position, Real3 lower, Real3 upper)
{
  PlaneRegion r;
  r.normal = normal;
  r.position = position;
  r.shape = Shape::rectangle;
  r.lower = lower;
  r.upper = upper;
  return r;
}

double PlaneRegion::covered_fraction(double a0, double a1, double b0, double b1) const
{
  const int b = (normal + 1) % 3, c = (normal + 2) % 3;
  if (shape == Shape::rectangle) {
    const double la = std::max(0.0, std::min(a1, upper[b]) - std::max(a0, lower[b]));
    const double lb = std::max(0.0, std::min(b1, upper[c]) - std::max(b0, lower[c]));
    return la * lb / ((a1 - a0) * (b1 - b0));
  }
  // Disk: exact when the square is wholly inside or outside, else a 16 x 16 midpoint sampling.
  const double ca = center[b], cb = center[c], r2 = radius * radius;
  const double near_a = std::clamp(ca, a0, a1) - ca, near_b = std::clamp(cb, b0, b1) - cb;
  if (near_a * near_a + near_b * near_b >= r2) return 0.0;
  const double far_a = std::max(std::abs(a0 - ca), std::abs(a1 - ca));
  const double far_b = std::max(std::abs(b0 - cb), std::abs(b1 - cb));
  if (far_a * far_a + far_b * far_b <= r2) return 1.0;
  constexpr int n = 16;
  int inside = 0;
  for (int p = 0; p < n; ++p)
    for (int q = 0; q < n; ++q) {
      const double x = a0 + (p + 0.5) * (a1 - a0) / n - ca, y = b0 + (q + 0.5) * (b1 - b0) / n - cb;
      if (x * x + y * y < r2) ++inside;
    }
  return static_cast<double>(inside) / (n * n);
}

double volume_flux(const NavierStokes& fluid, const PlaneRegion& region)
{
  const StaggeredGrid& grid = fluid.grid();
  const int a = region.normal, b = (a + 1) % 3, c = (a + 2) % 3;
  const PetscInt n = grid.cells(a);
  const double s = (region.position - grid.box().lower[a]) / grid.h(a);
  // The face planes around the region's plane and their interpolation weights.
  auto i0 = static_cast<PetscInt>(std::floor(s));
  double f = s - static_cast<double>(i0);
  if (f > 1.0 - 1e-9) {
    ++i0;
    f = 0.0;
  }
  PetscInt planes[2] = {i0, i0 + 1};
  const double weights[2] = {1.0 - f, f};
  for (auto& p : planes) {
    if (grid.periodic(a))
      p = ((p % n) + n) % n;
    else
      p = std::clamp<PetscInt>(p, 0, n);
  }
  StagArray u(grid, fluid.state(), true);
  const PetscInt slot = grid.face_slot(a);
  double flux = 0.0;
  for_owned_faces(grid, a, [&](PetscInt i, PetscInt j, PetscInt k) {
    const Index3 idx{i, j, k};
    double w = 0.0;
    for (int q = 0; q < 2; ++q)
      if (weights[q] > 1e-12 && idx[a] == planes[q]) w += weights[q];
    if (w == 0.0) return;
    const Real3 x = grid.face_position(a, i, j, k);
    const double hb = grid.h(b), hc = grid.h(c);
    const double fraction =
        region.covered_fraction(x[b] - 0.5 * hb, x[b] + 0.5 * hb, x[c] - 0.5 * hc, x[c] + 0.5 * hc);
    flux += w * fraction * u(i, j, k, slot) * hb * hc;
  });
  return sum_all(grid, flux);
}

Real3 velocity_at(const NavierStokes& fluid, const Real3& x)
{
  const StaggeredGrid& grid = fluid.grid();
  Real3 v{};
  for (int d = 0; d < 3; ++d) {
    Real3 offset{0.5, 0.5, 0.5};
    offset[d] = 0.0;
    v[d] = sum_all(grid, interpolate(grid, fluid.state(), grid.face_slot(d), offset, x));
  }
  return v;
}

double pressure_at(const NavierStokes& fluid, const Real3& x)
{
  const StaggeredGrid& grid = fluid.grid();
  return sum_all(grid, interpolate(grid, fluid.state(), grid.pressure_slot(), {0.5, 0.5, 0.5}, x));
}

double max_velocity_magnitude(const NavierStokes& fluid, const PointSet& region)
{
  const StaggeredGrid& grid = fluid.grid();
  StagArray u(grid, fluid.state(), true);
  double largest = 0.0;
  for_owned_cells(grid, [&](PetscInt i, PetscInt j, PetscInt k) {
    if (region && !region(grid.cell_center(i, j, k))) return;
    double m2 = 0.0;
    for (int d = 0; d < 3; ++d) {
      Index3 up{i, j, k};
      up[d] += 1;
      const double c = 0.5 * (u(i, j, k, grid.face_slot(d)) + u(up[0], up[1], up[2], grid.face_slot(d)));
      m2 += c * c;
    }
    largest = std::max(largest, m2);
  });
  return std::sqrt(max_all(grid, largest));
}

double kinetic_energy(const NavierStokes& fluid)
{
  const StaggeredGrid& grid = fluid.grid();
  StagArray u(grid, fluid.state(), true);
  double sum = 0.0;
  for (int d = 0; d < 3; ++d)
    for_owned_faces(grid, d, [&](PetscInt i, PetscInt j, PetscInt k) {
      const double v = u(i, j, k, grid.face_slot(d));
      sum += face_weight(grid, d, Index3{i, j, k}[d]) * v * v;
    });
  return 0.5 * fluid.settings().rho * grid.cell_volume() * sum_all(grid, sum);
}

double enstrophy(const NavierStokes& fluid)
{
  const StaggeredGrid& grid = fluid.grid();
  StagArray u(grid, fluid.state(), true);
  double sum = 0.0;
  for_owned_cells(grid, [&](PetscInt i, PetscInt j, PetscInt k) {
    for (int a = 0; a < 3; ++a) {
      const double w = cell_vorticity(grid, u, a, i, j, k);
      sum += w * w;
    }
  });
  return 0.5 * grid.cell_volume() * sum_all(grid, sum);
}

double max_divergence(const NavierStokes& fluid)
{
  const StaggeredGrid& grid = fluid.grid();
  StagArray u(grid, fluid.state(), true);
  double largest = 0.0;
  for_owned_cells(grid, [&](PetscInt i, PetscInt j, PetscInt k) {
    double div = 0.0;
    for (int d = 0; d < 3; ++d) {
      Index3 up{i, j, k};
      up[d] += 1;
      div += (u(up[0], up[1], up[2], grid.face_slot(d)) - u(i, j, k, grid.face_slot(d))) / grid.h(d);
    }
    largest = std::max(largest, std::abs(div));
  });
  return max_all(grid, largest);
}

CellFields cell_fields(const NavierStokes& fluid)
{
  const StaggeredGrid& grid = fluid.grid();
  CellFields out;
  for (int d = 0; d < 3; ++d) {
    out.begin[d] = grid.begin(d);
    out.count[d] = grid.count(d);
  }
  const auto cells = static_cast<std::size_t>(grid.count(0) * grid.count(1) * grid.count(2));
  out.velocity.reserve(3 * cells);
  out.vorticity.reserve(3 * cells);
  out.pressure.reserve(cells);
  StagArray u(grid, fluid.state(), true);
  for_owned_cells(grid, [&](PetscInt i, PetscInt j, PetscInt k) {
    for (int d = 0; d < 3; ++d) {
      Index3 up{i, j, k};
      up[d] += 1;
      out.velocity.push_back(0.5 *
                             (u(i, j, k, grid.face_slot(d)) + u(up[0], up[1], up[2], grid.face_slot(d))));
    }
    for (int a = 0; a < 3; ++a) out.vorticity.push_back(cell_vorticity(grid, u, a, i, j, k));
    out.pressure.push_back(u(i, j, k, grid.pressure_slot()));
  });
  return out;
}

FieldErrors field_errors(const NavierStokes& fluid, const VelocityFunction& exact_velocity,
                         const ScalarFunction& exact_pressure, bool pressure_up_to_constant)
{
  const StaggeredGrid& grid = fluid.grid();
  StagArray u(grid, fluid.state(), true);
  const double volume = grid.box().length(0) * grid.box().length(1) * grid.box().length(2);
  FieldErrors e;
  double sum = 0.0;
  for (int d = 0; d < 3; ++d)
    for_owned_faces(grid, d, [&](PetscInt i, PetscInt j, PetscInt k) {
      const double err =
          u(i, j, k, grid.face_slot(d)) - exact_velocity(grid.face_position(d, i, j, k), fluid.time())[d];
      sum += face_weight(grid, d, Index3{i, j, k}[d]) * err * err;
      e.velocity_max = std::max(e.velocity_max, std::abs(err));
    });
  e.velocity_l2 = std::sqrt(sum_all(grid, sum) * grid.cell_volume() / volume);
  e.velocity_max = max_all(grid, e.velocity_max);
  const double tp = fluid.pressure_time();
  double mean_numeric = 0.0, mean_exact = 0.0;
  if (pressure_up_to_constant) {
    for_owned_cells(grid, [&](PetscInt i, PetscInt j, PetscInt k) {
      mean_numeric += u(i, j, k, grid.pressure_slot());
      mean_exact += exact_pressure(grid.cell_center(i, j, k), tp);
    });
    const double n = static_cast<double>(grid.cells(0) * grid.cells(1) * grid.cells(2));
    mean_numeric = sum_all(grid, mean_numeric) / n;
    mean_exact = sum_all(grid, mean_exact) / n;
  }
  sum = 0.0;
  for_owned_cells(grid, [&](PetscInt i, PetscInt j, PetscInt k) {
    const double err = (u(i, j, k, grid.pressure_slot()) - mean_numeric) -
                       (exact_pressure(grid.cell_center(i, j, k), tp) - mean_exact);
    sum += err * err;
    e.pressure_max = std::max(e.pressure_max, std::abs(err));
  });
  e.pressure_l2 = std::sqrt(sum_all(grid, sum) * grid.cell_volume() / volume);
  e.pressure_max = max_all(grid, e.pressure_max);
  return e;
}

} // namespace ibvalve::fluid
