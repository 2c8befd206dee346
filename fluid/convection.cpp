#include "fluid/convection.hpp"

#include <vector>

namespace ibvalve::fluid {

namespace {

/// a times the face value upwind of a: (um, u0, up, upp) run along +e, the side between u0 and up.
inline double upwind_flux(double a, double um, double u0, double up, double upp, ConvectionScheme scheme)
{
  if (scheme == ConvectionScheme::centered) return a * 0.5 * (u0 + up);
  // The stencil is mirrored by selects rather than a branch on the sign of a, which changes from
  // side to side wherever the flow recirculates.
  const bool forward = a >= 0.0;
  const double wm = select(forward, um, upp), w0 = select(forward, u0, up), wp = select(forward, up, u0),
               wpp = select(forward, upp, um);
  return a * limited_face_value(wm, w0, wp, wpp);
}

/// Tangential velocity on a wall: the data of a velocity side, zero on a traction side.
struct WallValues {
  const StaggeredGrid& grid;
  const BoundaryConditions& bc;
  double t;
  /// The point of side (e, upper) beside face idx of u_d.
  Real3 side_point(int e, int upper, int d, const Index3& idx) const
  {
    Real3 x = grid.face_position(d, idx[0], idx[1], idx[2]);
    x[e] = upper ? grid.box().upper[e] : grid.box().lower[e];
    return x;
  }
  double tangential(int e, int upper, int d, const Index3& idx) const
  {
    const int s = side_index(e, upper);
    if (bc.side(s).kind != SideKind::velocity) return 0.0;
    return bc.velocity(s, side_point(e, upper, d, idx), t)[d];
  }
  /// Whether the side's point beside face idx of u_d is open (traction), not walled.
  bool open(int e, int upper, int d, const Index3& idx) const
  {
    return bc.traction_at(side_index(e, upper), side_point(e, upper, d, idx));
  }
};

} // namespace

void convective_term(const StaggeredGrid& grid, const BoundaryConditions& bc, double t, Vec u_local,
                     Vec out_local, ConvectionScheme scheme)
{
  const WallValues wall{grid, bc, t};
  StagArray u(grid, u_local, true);
  StagArray out(grid, out_local);
  std::vector<double> flux;
  for (int d = 0; d < 3; ++d) {
    const PetscInt sd = grid.face_slot(d);
    const Index3 lo{grid.begin(0), grid.begin(1), grid.begin(2)};
    const Index3 hi{grid.face_end(d, 0), grid.face_end(d, 1), grid.face_end(d, 2)};
    for (PetscInt k = lo[2]; k < hi[2]; ++k)
      for (PetscInt j = lo[1]; j < hi[1]; ++j)
        for (PetscInt i = lo[0]; i < hi[0]; ++i) out(i, j, k, sd) = 0.0;
    for (int e = 0; e < 3; ++e) {
      const PetscInt se = grid.face_slot(e);
      const PetscInt oi = e == 0, oj = e == 1, ok = e == 2; // unit step along e
      // The flux through the lower side (along e) of every momentum cell, and of the one past the
      // last, each computed once: F(idx) = a q, the advecting velocity a times the upwind-biased
      // advected value q. For e == d the side is the cell centre between faces idx - e and idx; for
      // e != d it is the edge between u_d at idx - e and idx.
      const PetscInt nx = hi[0] - lo[0] + oi, ny = hi[1] - lo[1] + oj, nz = hi[2] - lo[2] + ok;
      flux.resize(static_cast<std::size_t>(nx * ny * nz));
      auto at = [&](PetscInt i, PetscInt j, PetscInt k) -> double& {
        return flux[static_cast<std::size_t>(((k - lo[2]) * ny + (j - lo[1])) * nx + (i - lo[0]))];
      };
      const PetscInt step_e = u.stride(e), step_d = u.stride(d), step_x = u.stride(0);
      for (PetscInt k = lo[2]; k < lo[2] + nz; ++k)
        for (PetscInt j = lo[1]; j < lo[1] + ny; ++j) {
          // Walk x with a pointer at u_d of face (i, j, k); neighbours along e are step_e apart, and
          // the advecting component e of the same element is (se - sd) away.
          const PetscScalar* p = &u(lo[0], j, k, sd);
          double* target = &at(lo[0], j, k);
          if (e == d)
            for (PetscInt i = 0; i < nx; ++i, p += step_x)
              target[i] =
                  upwind_flux(0.5 * (p[-step_e] + p[0]), p[-2 * step_e], p[-step_e], p[0], p[step_e], scheme);
          else
            for (PetscInt i = 0; i < nx; ++i, p += step_x)
              target[i] = upwind_flux(0.5 * (p[se - sd] + p[se - sd - step_d]), p[-2 * step_e], p[-step_e],
                                      p[0], p[step_e], scheme);
        }
      if (e != d && !grid.periodic(e)) {
        // A side on a wall carries the wall's tangential velocity, known exactly. Where fluid leaves
        // through a traction side it carries the value extrapolated linearly from the two cells it
        // leaves: the side's zero when the layer beside the side is resolved (exact for a linear
        // profile through it, so second order), the cells' own momentum when it is not. The side's
        // zero taken as the outflow's value leaves that momentum behind, piling up in the boundary
        // cell at u_n u_t / h (in a box's corner between two such sides, fed from both:
        // tests/fluid/test_outflow_momentum.cpp).
        for (int upper = 0; upper < 2; ++upper) {
          const PetscInt layer = upper ? grid.cells(e) : 0;
          Index3 first = lo, last{lo[0] + nx, lo[1] + ny, lo[2] + nz};
          if (layer < first[e] || layer >= last[e]) continue;
          first[e] = layer;
          last[e] = layer + 1;
          for (PetscInt k = first[2]; k < last[2]; ++k)
            for (PetscInt j = first[1]; j < last[1]; ++j)
              for (PetscInt i = first[0]; i < last[0]; ++i) {
                const Index3 idx{i, j, k};
                const PetscScalar* p = &u(i, j, k, sd);
                const double a = 0.5 * (p[se - sd] + p[se - sd - step_d]);
                const bool outflow = upper ? a > 0.0 : a < 0.0;
                const double extrapolated =
                    upper ? 1.5 * p[-step_e] - 0.5 * p[-2 * step_e] : 1.5 * p[0] - 0.5 * p[step_e];
                at(i, j, k) = outflow && wall.open(e, upper, d, idx) ? a * extrapolated
                                                                     : a * wall.tangential(e, upper, d, idx);
              }
        }
      }
      const double inv_h = 1.0 / grid.h(e);
      for (PetscInt k = lo[2]; k < hi[2]; ++k)
        for (PetscInt j = lo[1]; j < hi[1]; ++j)
          for (PetscInt i = lo[0]; i < hi[0]; ++i)
            out(i, j, k, sd) += (at(i + oi, j + oj, k + ok) - at(i, j, k)) * inv_h;
    }
  }
}

} // namespace ibvalve::fluid
