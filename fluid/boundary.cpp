#include "fluid/boundary.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <stdexcept>

namespace ibvalve::fluid {

std::string side_name(int side)
{
  static const char* names[6] = {"x_lower", "x_upper", "y_lower", "y_upper", "z_lower", "z_upper"};
  return names[side];
}

bool BoundaryConditions::any_traction() const
{
  for (const auto& s : sides_)
    if (s.kind == SideKind::traction) return true;
  return false;
}

void BoundaryConditions::check(const BoxGeometry& box) const
{
  for (int d = 0; d < 3; ++d) {
    const bool lower = side(d, 0).kind == SideKind::periodic, upper = side(d, 1).kind == SideKind::periodic;
    if (lower != upper)
      throw std::invalid_argument("fluid boundary: " + side_name(side_index(d, 0)) + " and " +
                                  side_name(side_index(d, 1)) + " must both be periodic or neither");
    if (lower != box.periodic[d])
      throw std::invalid_argument(
          fmt::format("fluid boundary: periodicity of direction {} does not match the grid", d));
  }
}

Real3 BoundaryConditions::velocity(int s, const Real3& x, double t) const
{
  const BoundarySide& b = sides_[s];
  if (b.kind != SideKind::velocity || !b.velocity) return {0.0, 0.0, 0.0};
  return b.velocity(x, t);
}

double BoundaryConditions::pressure(int s, const Real3& x, double t) const
{
  const BoundarySide& b = sides_[s];
  if (b.kind != SideKind::traction) return 0.0;
  return (b.pressure ? b.pressure(x, t) : 0.0) - backflow_drop(s, x);
}

void BoundaryConditions::set_backflow_drop(int s, const BoxGeometry& box, std::vector<double> drop)
{
  drop_box_ = box;
  backflow_drop_[s] = std::move(drop);
}

double BoundaryConditions::backflow_drop(int s, const Real3& x) const
{
  const auto& drop = backflow_drop_[s];
  if (drop.empty()) return 0.0;
  const int a = s / 2, b = (a + 1) % 3, c = (a + 2) % 3;
  auto cell = [&](int d) {
    const double h = drop_box_.spacing(d);
    const auto i = static_cast<PetscInt>(std::floor((x[d] - drop_box_.lower[d]) / h));
    return std::clamp<PetscInt>(i, 0, drop_box_.cells[d] - 1); // ghost points outside: the nearest face
  };
  return drop[static_cast<std::size_t>(cell(c) * drop_box_.cells[b] + cell(b))];
}

bool BoundaryConditions::traction_at(int s, const Real3& x) const
{
  const BoundarySide& b = sides_[s];
  return b.kind == SideKind::traction && !(b.wall && b.wall(x));
}

namespace {

/// Calls f(i, j, k) over the ghosted range of the two directions other than `a`, with index `ia`
/// along a.
template <class F>
void for_plane(const StaggeredGrid& grid, int a, PetscInt ia, F&& f)
{
  const int b = (a + 1) % 3, c = (a + 2) % 3;
  for (PetscInt ic = grid.ghost_begin(c); ic < grid.ghost_end(c); ++ic)
    for (PetscInt ib = grid.ghost_begin(b); ib < grid.ghost_end(b); ++ib) {
      Index3 idx{};
      idx[a] = ia;
      idx[b] = ib;
      idx[c] = ic;
      f(idx);
    }
}

} // namespace

void set_boundary_normal_velocity(const StaggeredGrid& grid, const BoundaryConditions& bc, Vec local,
                                  double t)
{
  StagArray u(grid, local);
  for (int a = 0; a < 3; ++a) {
    if (bc.periodic(a)) continue;
    for (int upper = 0; upper < 2; ++upper) {
      const int s = side_index(a, upper);
      const BoundarySide& side = bc.side(s);
      if (side.kind == SideKind::periodic || (side.kind == SideKind::traction && !side.wall)) continue;
      if (upper ? !grid.owns_upper(a) : !grid.owns_lower(a)) continue;
      const PetscInt ia = upper ? grid.cells(a) : 0;
      for_plane(grid, a, ia, [&](const Index3& i) {
        const Real3 x = grid.face_position(a, i[0], i[1], i[2]);
        if (!bc.traction_at(s, x)) u(i[0], i[1], i[2], grid.face_slot(a)) = bc.velocity(s, x, t)[a];
      });
    }
  }
}

void fill_ghosts(const StaggeredGrid& grid, const BoundaryConditions& bc, Vec local, double t)
{
  StagArray u(grid, local);
  const PetscInt ps = grid.pressure_slot();
  for (int a = 0; a < 3; ++a) {
    if (bc.periodic(a)) continue;
    const PetscInt n = grid.cells(a);
    for (int upper = 0; upper < 2; ++upper) {
      if (upper ? !grid.owns_upper(a) : !grid.owns_lower(a)) continue;
      const int s = side_index(a, upper);
      const bool traction = bc.side(s).kind == SideKind::traction;
      const double wall = upper ? grid.box().upper[a] : grid.box().lower[a];
      const PetscInt depth = upper ? grid.ghost_end(a) - n : -grid.ghost_begin(a); // ghost cells outside
      for (PetscInt m = 1; m <= depth; ++m) {
        // Cell-centred ghost (tangential velocity, pressure) and its mirror image inside.
        const PetscInt ghost_cell = upper ? n - 1 + m : -m, mirror_cell = upper ? n - m : m - 1;
        for_plane(grid, a, ghost_cell, [&](const Index3& g) {
          Index3 in = g;
          in[a] = mirror_cell;
          for (int d = 0; d < 3; ++d) {
            if (d == a) continue;
            Real3 x = grid.face_position(d, g[0], g[1], g[2]);
            x[a] = wall;
            const double value = traction ? 0.0 : bc.velocity(s, x, t)[d];
            const PetscInt sd = grid.face_slot(d);
            if (m == 1) {
              // Quadratic extrapolation through the wall value (exact for parabolic profiles):
              // u_ghost = 8/3 g - 2 u_0 + 1/3 u_1.
              Index3 in1 = in;
              in1[a] += upper ? -1 : 1;
              u(g[0], g[1], g[2], sd) =
                  8.0 / 3.0 * value - 2.0 * u(in[0], in[1], in[2], sd) + u(in1[0], in1[1], in1[2], sd) / 3.0;
            } else {
              u(g[0], g[1], g[2], sd) = 2.0 * value - u(in[0], in[1], in[2], sd);
            }
          }
          const double p_in = u(in[0], in[1], in[2], ps);
          Real3 xc = grid.cell_center(g[0], g[1], g[2]);
          xc[a] = wall;
          if (traction && bc.traction_at(s, xc)) {
            u(g[0], g[1], g[2], ps) = 2.0 * bc.pressure(s, xc, t) - p_in;
          } else {
            u(g[0], g[1], g[2], ps) = p_in;
          }
        });
        // Normal-velocity ghost face n + m (or -m) and its mirror n - m (or m), about the boundary face.
        const PetscInt ghost_face = upper ? n + m : -m, mirror_face = upper ? n - m : m,
                       wall_face = upper ? n : 0;
        if (upper && ghost_face >= grid.ghost_end(a)) continue;
        for_plane(grid, a, ghost_face, [&](const Index3& g) {
          Index3 in = g, w = g;
          in[a] = mirror_face;
          w[a] = wall_face;
          const double inside = u(in[0], in[1], in[2], grid.face_slot(a));
          const double on_wall = u(w[0], w[1], w[2], grid.face_slot(a));
          Real3 xw = grid.face_position(a, w[0], w[1], w[2]);
          const bool free = traction && bc.traction_at(s, xw);
          u(g[0], g[1], g[2], grid.face_slot(a)) = free ? inside : 2.0 * on_wall - inside;
        });
      }
    }
  }
}

} // namespace ibvalve::fluid
