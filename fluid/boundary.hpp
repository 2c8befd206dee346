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
//
// Backflow stabilization: a traction side with `backflow` = beta > 0 lowers its pressure where fluid
// enters, p_b - beta rho/2 (u.n)^2 where u.n < 0 (n the outward normal), with u.n of the current
// state. With the prescribed static pressure alone, fluid entering through a traction side brings its
// kinetic energy in for free, and a thin fast inflow next to a slow outflow through the same side
// grows without bound (backflow divergence, Esmaily Moghadam et al. 2011, Comput. Mech. 48:277; the
// traction term beta rho/2 (u.n)_- u of Bazilevs et al. 2009, CMAME 198:3534, here for its normal
// part). With beta = 1 the prescribed value is the total pressure of the inflow (Bernoulli from a
// reservoir at rest).
#include <array>
#include <functional>
#include <string>
#include <vector>

#include <petscvec.h>

#include "fluid/grid.hpp"

namespace ibvalve::fluid {

using VelocityFunction = std::function<Real3(const Real3& x, double t)>;
using ScalarFunction = std::function<double(const Real3& x, double t)>;
/// A region of the box: whether it holds the point x (cm).
using PointSet = std::function<bool(const Real3& x)>;

enum class SideKind { periodic, velocity, traction };

struct BoundarySide {
  SideKind kind = SideKind::periodic;
  VelocityFunction velocity;                // velocity sides; empty = no slip
  ScalarFunction pressure;                  // traction sides: p_b = -n.sigma.n; empty = zero
  std::function<bool(const Real3& x)> wall; // traction sides: true where the side is a no-slip wall
  double backflow = 0.0;                    // traction sides: backflow stabilization beta (0 = none)
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

  /// Rigid walls inside the box (fluid/solid_cells.hpp): the cells whose centre `region` holds are
  /// blocked, the fluid at rest in them. Only the Krylov solver on one grid takes them. Empty = none.
  void set_solid(PointSet region) { solid_ = std::move(region); }
  const PointSet& solid() const { return solid_; }

  /// The backflow pressure drop beta rho/2 (u.n)_-^2 of side s at each of its boundary faces (box
  /// cells of the side's plane, index c * n_b + b with b = (a + 1) % 3, c = (a + 2) % 3 for the side's
  /// direction a), subtracted from the side's pressure by pressure(). Set by the integrator from its
  /// state; empty = none.
  void set_backflow_drop(int s, const BoxGeometry& box, std::vector<double> drop);
  /// The drop at the boundary point x of side s (0 without one).
  double backflow_drop(int s, const Real3& x) const;

 private:
  std::array<BoundarySide, 6> sides_{};
  std::array<std::vector<double>, 6> backflow_drop_{};
  BoxGeometry drop_box_{};
  PointSet solid_;
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
