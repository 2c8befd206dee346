#include "fluid/convection.hpp"

namespace ibvalve::fluid {

namespace {

inline double upwind_flux(double a, double um, double u0, double up, double upp, ConvectionScheme scheme)
{
  if (scheme == ConvectionScheme::centered) return a * 0.5 * (u0 + up);
  return a * (a >= 0.0 ? limited_face_value(um, u0, up, upp) : limited_face_value(upp, up, u0, um));
}

/// Tangential velocity on a wall: the data of a velocity side, zero on a traction side.
struct WallValues {
  const StaggeredGrid& grid;
  const BoundaryConditions& bc;
  double t;
  double tangential(int e, int upper, int d, const Index3& idx) const
  {
    const int s = side_index(e, upper);
    if (bc.side(s).kind != SideKind::velocity) return 0.0;
    Real3 x = grid.face_position(d, idx[0], idx[1], idx[2]);
    x[e] = upper ? grid.box().upper[e] : grid.box().lower[e];
    return bc.velocity(s, x, t)[d];
  }
};

} // namespace

void convective_term(const StaggeredGrid& grid, const BoundaryConditions& bc, double t, Vec u_local,
                     Vec out_local, ConvectionScheme scheme)
{
  const WallValues wall{grid, bc, t};
  StagArray u(grid, u_local, true);
  StagArray out(grid, out_local);
  for (int d = 0; d < 3; ++d) {
    const PetscInt sd = grid.face_slot(d);
    for (PetscInt k = grid.begin(2); k < grid.face_end(d, 2); ++k)
      for (PetscInt j = grid.begin(1); j < grid.face_end(d, 1); ++j)
        for (PetscInt i = grid.begin(0); i < grid.face_end(d, 0); ++i) {
          double total = 0.0;
          for (int e = 0; e < 3; ++e) {
            const PetscInt se = grid.face_slot(e);
            const PetscInt oi = e == 0, oj = e == 1, ok = e == 2; // unit step along e
            const PetscInt di = d == 0, dj = d == 1, dk = d == 2; // unit step along d
            auto ud = [&](PetscInt s) { return u(i + s * oi, j + s * oj, k + s * ok, sd); };
            // Advecting velocity on the upper (+) and lower (-) sides of the control volume along e.
            double a_plus, a_minus;
            if (e == d) {
              a_plus = 0.5 * (ud(0) + ud(1));
              a_minus = 0.5 * (ud(-1) + ud(0));
            } else {
              a_plus = 0.5 * (u(i + oi, j + oj, k + ok, se) + u(i + oi - di, j + oj - dj, k + ok - dk, se));
              a_minus = 0.5 * (u(i, j, k, se) + u(i - di, j - dj, k - dk, se));
            }
            // For e == d the sides are cell centres between faces s and s+1; for e != d they are the
            // edges between u_d at s and s+1 along e. Either way the same four values enter.
            double f_plus = upwind_flux(a_plus, ud(-1), ud(0), ud(1), ud(2), scheme);
            double f_minus = upwind_flux(a_minus, ud(-2), ud(-1), ud(0), ud(1), scheme);
            if (e != d && !grid.periodic(e)) {
              // An edge on a wall carries the wall's tangential velocity, known exactly.
              const Index3 idx{i, j, k};
              if (idx[e] == 0) f_minus = a_minus * wall.tangential(e, 0, d, idx);
              if (idx[e] == grid.cells(e) - 1) f_plus = a_plus * wall.tangential(e, 1, d, idx);
            }
            total += (f_plus - f_minus) / grid.h(e);
          }
          out(i, j, k, sd) = total;
        }
  }
}

} // namespace ibvalve::fluid
