#pragma once
// Boundary conditions on the six sides of the box, each a function of position and time.
//
// A side is periodic (its opposite side too), a velocity side (the full velocity vector is given:
// no-slip walls, prescribed inflow), or a traction side: the normal traction n.sigma.n = -p_b is
// given through the boundary pressure p_b(x, t) and the tangential velocity is zero. With zero
// tangential velocity on the side, continuity gives du_n/dn = 0 there, so n.sigma.n = -p + 2 mu
// du_n/dn = -p: the side is a Dirichlet condition for the pressure and a Neumann condition for the
// normal velocity (the formulation of Griffith 2009, JCP 228:7565, section 3.2).
//
// A traction side may be a wall in part: where its `wall(x)` is true the side is a no-slip wall (u = 0)
// instead. A vessel whose lumen meets an inlet or outlet side gets its pressure in the lumen and a
// closed side around it (the set-up of Griffith 2012, Int. J. Numer. Meth. Biomed. Engng. 28:317), so
// no flow goes around the vessel's end.
#include <array>
#include <functional>
#include <string>

#include <petscvec.h>

#include "fluid/grid.hpp"

namespace ibvalve::fluid {

using VelocityFunction = std::function<Real3(const Real3& x, double t)>;
using ScalarFunction = std::function<double(const Real3& x, double t)>;

enum class SideKind { periodic, velocity, traction };

struct BoundarySide {
  SideKind kind = SideKind::periodic;
  VelocityFunction velocity;                // velocity sides; empty = no slip
  ScalarFunction pressure;                  // traction sides: p_b = -n.sigma.n; empty = zero
  std::function<bool(const Real3& x)> wall; // traction sides: true where the side is a no-slip wall
};

/// The side index of direction d (0 = x, 1 = y, 2 = z), lower (0) or upper (1): 2 d + upper.
constexpr int side_index(int d, int upper)
{
  return 2 * d + upper;
}
std::string side_name(int side); // "x_lower", ...

class BoundaryConditions {
 public:
  BoundaryConditions() = default;
  /// All sides periodic.
  static BoundaryConditions all_periodic() { return {}; }

  BoundarySide& side(int s) { return sides_[s]; }
  const BoundarySide& side(int s) const { return sides_[s]; }
  BoundarySide& side(int d, int upper) { return sides_[side_index(d, upper)]; }
  const BoundarySide& side(int d, int upper) const { return sides_[side_index(d, upper)]; }

  bool periodic(int d) const { return sides_[side_index(d, 0)].kind == SideKind::periodic; }
  /// True when some side is a traction side (the pressure then has no free constant).
  bool any_traction() const;
  /// Throws std::invalid_argument unless the periodic sides pair up and match the box.
  void check(const BoxGeometry& box) const;

  Real3 velocity(int s, const Real3& x, double t) const;
  double pressure(int s, const Real3& x, double t) const;
  /// Whether the point x of side s carries a traction (a traction side, not walled there).
  bool traction_at(int s, const Real3& x) const;

 private:
  std::array<BoundarySide, 6> sides_{};
};

/// Sets the normal velocity on the boundary faces of velocity sides (and of the walled parts of traction
/// sides) of a local vector to the boundary data at time t (the values the discrete system then holds
/// fixed).
void set_boundary_normal_velocity(const StaggeredGrid& grid, const BoundaryConditions& bc, Vec local,
                                  double t);

/// Fills the ghost velocities outside the box of a local vector (after the exchange between ranks)
/// at time t: tangential components through the wall value g (first ghost by quadratic extrapolation
/// 8/3 g - 2 u_0 + 1/3 u_1, deeper ghosts by reflection 2 g - u_in),
/// normal components odd about the boundary value (velocity sides) or even (traction sides,
/// du_n/dn = 0). Pressure ghosts: even (velocity sides), odd about p_b (traction sides). The walled parts
/// of a traction side are treated as a velocity side there.
void fill_ghosts(const StaggeredGrid& grid, const BoundaryConditions& bc, Vec local, double t);

} // namespace ibvalve::fluid
