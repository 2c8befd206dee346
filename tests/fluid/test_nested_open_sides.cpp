// Traction (pressure) sides on nested levels (fluid/nested_navier_stokes.hpp): the unit cube with no-slip
// walls x = 0, 1 and y = 0, 1 (their tangential velocity given) and traction sides z = 0, 1, where the
// exact pressure is given. The exact flow is
//   u = a(t) (0, 0, b(r)) + c(t) (-pi sin(pi x) cos(pi y) sin(pi z), 0, -pi cos(pi x) cos(pi y) cos(pi z)),
// b = (1 - r^2/R^2)^4 inside r < R = 0.3 around the axis x = y = 1/2 (a jet through both traction sides,
// zero near the walls), a = 1 + sin(t)/2, c = 0.3 cos t; the second field has u_x = u_y = 0 and
// du_z/dz = 0 on z = 0, 1, as a traction side asks, and enters and leaves through both sides. p = (1/2 - z)
// + 0.2 cos t cos(pi x) cos(pi y) cos(pi z); the body force f = rho (du/dt + u.grad u) + grad p - mu lap u is
// computed from the exact fields by central differences (step 1e-4). Level 1 (ratio 2) is
// [2/8, 5/8] x [3/8, 6/8] x [0, 3/8]: it crosses the jet and lies on the side z = 0, so the side has
// traction faces on both levels. Backflow stabilization (beta = 1) lowers the side pressure by
// rho/2 (u.n)^2 where fluid enters; the exact side pressure handed to the solver adds that drop back
// (from the exact u at t^n, the state the solver takes the drop from), so a drop applied with the wrong
// sign, size or place shows as an O(1) error. Measured:
//  - velocity error orders (L2 with the faces' dual volumes, and max), pressure L2 orders;
//  - the divergence after every step on every level;
//  - volume in through z = 0 equals volume out through z = 1 (and a closed box crossing the interface);
//  - pressure probes (NestedNavierStokes::pressure_at) on both levels and beside the sides;
//  - the same with the sides walled outside the jet's disk (a vessel's lumen; only the jet, c = 0);
//  - 1 rank against 2 ranks.
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "fluid/nested_navier_stokes.hpp"
#include "io/petsc_check.hpp"
#include "tests/fluid/composite_norms.hpp"
#include "tests/fluid/manufactured_force.hpp"

namespace ibvalve::fluid {
namespace {

constexpr double pi = std::numbers::pi;
constexpr double nu = 0.05;
constexpr double jet_radius = 0.3;

struct Flow {
  double jet = 1.0;   // a(t) = jet (1 + sin(t)/2)
  double swirl = 0.3; // c(t) = swirl cos t; 0 = the jet alone
  double backflow = 1.0;
  bool walled = false; // the traction sides walled outside the jet's disk

  Real3 velocity(const Real3& x, double t) const
  {
    const double r2 = (x[0] - 0.5) * (x[0] - 0.5) + (x[1] - 0.5) * (x[1] - 0.5);
    const double s = 1.0 - r2 / (jet_radius * jet_radius);
    const double profile = s > 0.0 ? s * s * s * s : 0.0;
    const double a = jet * (1.0 + 0.5 * std::sin(t)), c = swirl * std::cos(t);
    return {-c * pi * std::sin(pi * x[0]) * std::cos(pi * x[1]) * std::sin(pi * x[2]), 0.0,
            a * profile - c * pi * std::cos(pi * x[0]) * std::cos(pi * x[1]) * std::cos(pi * x[2])};
  }
  double pressure(const Real3& x, double t) const
  {
    return (0.5 - x[2]) + 0.2 * std::cos(t) * std::cos(pi * x[0]) * std::cos(pi * x[1]) * std::cos(pi * x[2]);
  }
  Real3 force(const Real3& x, double t) const
  {
    return testing::manufactured_force([this](const Real3& y, double s) { return velocity(y, s); },
                                       [this](const Real3& y, double s) { return pressure(y, s); }, 1.0, nu,
                                       x, t);
  }
};

template <class... Args>
void report(const char* format, Args... args)
{
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0) std::printf(format, args...);
}

GridHierarchy make_hierarchy(PetscInt n0)
{
  BoxGeometry box;
  box.cells = {n0, n0, n0};
  box.periodic = {false, false, false};
  IndexBox fine;
  const Index3 lower{2, 3, 0}, upper{5, 6, 3};
  for (int d = 0; d < 3; ++d) {
    fine.lower[d] = lower[d] * 2 * n0 / 8;
    fine.upper[d] = upper[d] * 2 * n0 / 8;
  }
  return GridHierarchy(box, {FinerLevel{2, {fine}}});
}

BoundaryConditions open_box(const Flow& flow, double dt)
{
  BoundaryConditions bc;
  for (int d = 0; d < 2; ++d)
    for (const int upper : {0, 1}) {
      bc.side(d, upper).kind = SideKind::velocity;
      bc.side(d, upper).velocity = [flow](const Real3& x, double t) { return flow.velocity(x, t); };
    }
  for (const int upper : {0, 1}) {
    BoundarySide& side = bc.side(2, upper);
    side.kind = SideKind::traction;
    side.backflow = flow.backflow;
    // The exact pressure at t = t^{n+1/2} plus the drop the solver takes off, from u at t^n = t - dt/2.
    side.pressure = [flow, dt, upper](const Real3& x, double t) {
      const double u_n = (upper ? 1.0 : -1.0) * flow.velocity(x, t - 0.5 * dt)[2];
      return flow.pressure(x, t) + (u_n < 0.0 ? 0.5 * flow.backflow * u_n * u_n : 0.0);
    };
    if (flow.walled)
      side.wall = [](const Real3& x) { return std::hypot(x[0] - 0.5, x[1] - 0.5) >= jet_radius; };
  }
  return bc;
}

struct Result {
  double l2 = 0.0, max = 0.0, pressure_l2 = 0.0;
  double divergence = 0.0;   // largest over steps and levels of max|D u| h_l / max|u|
  double through_flux = 0.0; // |in - out| / |in| over the steps
  double closed_flux = 0.0;  // |net outflow| / sum of |side fluxes| of a box crossing the interface
  double inflow = 0.0;       // the last step's volume flux in through z = 0
  double probe_error = 0.0;  // largest |pressure_at - p| at five probes on both levels
  PetscInt pressure_iterations = 0;
  std::vector<double> u;
};

Result run(MPI_Comm comm, PetscInt n0, const Flow& flow, bool gather = false, double end = 0.125)
{
  const GridHierarchy h = make_hierarchy(n0);
  const double dt = 0.125 / static_cast<double>(n0);
  FluidSettings settings;
  settings.convection = ConvectionScheme::centered; // second order on smooth flows (docs/nested.md)
  settings.mu = nu;
  NestedNavierStokes fluid(comm, h, open_box(flow, dt), settings);
  const VelocityFunction u = [&](const Real3& x, double t) { return flow.velocity(x, t); };
  fluid.set_initial_condition(
      u, [&](const Real3& x, double t) { return flow.pressure(x, t - 0.5 * dt); }, 0.0);
  const int steps = static_cast<int>(std::lround(end / dt));
  Result r;
  for (int s = 0; s < steps; ++s) {
    fluid.set_body_force([&](const Real3& x, double t) { return flow.force(x, t); }, fluid.time() + 0.5 * dt);
    fluid.step(dt);
    double u_max = 0.0;
    PETSC_CHECK(VecNorm(fluid.velocity(), NORM_INFINITY, &u_max));
    const auto div = fluid.max_divergence_by_level();
    for (int l = 0; l < h.levels(); ++l) r.divergence = std::max(r.divergence, div[l] * h.h(l, 0) / u_max);
    const Real3 lower{0.0, 0.0, 0.0}, upper{1.0, 1.0, 1.0};
    r.inflow = fluid.flux(PlaneRegion::rectangle(2, 0.0, lower, upper));
    const double outflow = fluid.flux(PlaneRegion::rectangle(2, 1.0, lower, upper));
    r.through_flux = std::max(r.through_flux, std::abs(r.inflow - outflow) / std::abs(r.inflow));
    // [1/2, 7/8] x [2/8, 7/8] x [1/8, 5/8]: x = 1/2 and z = 3/8 cut through level 1.
    const Real3 box_lower{0.5, 0.25, 0.125}, box_upper{0.875, 0.875, 0.625};
    double net = 0.0, total = 0.0;
    for (int d = 0; d < 3; ++d)
      for (const int side : {0, 1}) {
        const double q =
            fluid.flux(PlaneRegion::rectangle(d, side ? box_upper[d] : box_lower[d], box_lower, box_upper));
        net += side ? q : -q;
        total += std::abs(q);
      }
    r.closed_flux = std::max(r.closed_flux, std::abs(net) / total);
    r.pressure_iterations = std::max(r.pressure_iterations, fluid.pressure_iterations());
  }
  const CompositeOperators& ops = fluid.operators();
  const testing::CompositeNorms velocity_error = testing::face_error(
      ops, [&](const Real3& x) { return flow.velocity(x, fluid.time()); }, fluid.velocity());
  r.max = velocity_error.max;
  r.l2 = velocity_error.l2;
  {
    // The pressure is fixed by the sides: no constant to remove.
    const petsc::OwnedVec p = ops.create_cell_vector();
    ops.sample([&](const Real3& x) { return flow.pressure(x, fluid.pressure_time()); }, p);
    PETSC_CHECK(VecAXPY(p, -1.0, fluid.pressure()));
    r.pressure_l2 = testing::cell_norms(ops, p).l2;
  }
  {
    // Probes on level 1, beside the interface on level 0, in a corner and half a cell from each side.
    const std::vector<Real3> probes{
        {0.5, 0.5, 0.2}, {0.4, 0.5, 0.4}, {0.8, 0.2, 0.7}, {0.45, 0.5, 0.01}, {0.1, 0.9, 0.99}};
    const std::vector<double> p = fluid.pressure_at(probes);
    for (std::size_t q = 0; q < probes.size(); ++q)
      r.probe_error =
          std::max(r.probe_error, std::abs(p[q] - flow.pressure(probes[q], fluid.pressure_time())));
  }
  if (gather) r.u = fluid.composite_velocity().gather(fluid.velocity());
  return r;
}

void convergence(const Flow& flow, const char* name, std::vector<PetscInt> grids, double pressure_order = 1.8)
{
  std::vector<Result> r;
  for (const PetscInt n0 : grids) {
    r.push_back(run(PETSC_COMM_WORLD, n0, flow));
    const Result& x = r.back();
    report("%s N0=%d: L2 %.3e max %.3e; pressure L2 %.3e; divergence %.1e; in - out %.1e (in %.4f); "
           "closed-box flux %.1e; projection iterations %d\n",
           name, static_cast<int>(n0), x.l2, x.max, x.pressure_l2, x.divergence, x.through_flux, x.inflow,
           x.closed_flux, static_cast<int>(x.pressure_iterations));
  }
  const auto order = [&](double Result::*e, std::size_t a) { return std::log2(r[a].*e / r[a + 1].*e); };
  for (std::size_t a = 0; a + 1 < r.size(); ++a)
    report("%s orders N0=%d -> %d: L2 %.2f, max %.2f, pressure L2 %.2f\n", name, static_cast<int>(grids[a]),
           static_cast<int>(grids[a + 1]), order(&Result::l2, a), order(&Result::max, a),
           order(&Result::pressure_l2, a));
  const std::size_t last = r.size() - 2;
  // Pressure probes: trilinear between cell centres (O(h^2)) on a second-order pressure.
  report("%s pressure probes: largest error %.2e, %.2e, %.2e\n", name, r[0].probe_error, r[1].probe_error,
         r.back().probe_error);
  EXPECT_GE(order(&Result::probe_error, last), 1.5) << name;
  EXPECT_GE(order(&Result::l2, last), 1.9) << name;
  EXPECT_GE(order(&Result::max, last), 1.5) << name;
  EXPECT_GE(order(&Result::pressure_l2, last), pressure_order) << name;
  for (const Result& x : r) {
    EXPECT_LT(x.divergence, 1e-10) << name;
    EXPECT_LT(x.through_flux, 1e-10) << name;
    EXPECT_LT(x.closed_flux, 1e-10) << name;
  }
}

// Measured (2 ranks): L2 orders 2.20, 2.09; max 1.45, 1.87; pressure L2 1.87, 1.90 (N0 = 8 -> 16 -> 32).
// Without the backflow drop added back to the side pressure the error stays O(1): L2 orders 0.63, 0.06.
TEST(NestedOpenSides, PressureSidesWithBackflowSecondOrderDivergenceFreeConservative)
{
  convergence(Flow{}, "traction sides z", {8, 16, 32});
}

// Measured: L2 orders 2.22, 2.10; max 1.26, 1.86; pressure L2 2.06, 1.65. The pressure loses a little: the
// projection's increment phi is zero on the disk and has zero normal derivative on the walled rest of the
// side, and a solution of such a mixed problem is only as smooth as r^(1/2) around the circle where the two
// meet, so the O(dt) pressure splitting error converges more slowly there (the smooth exact pressure
// does not see the junction; the scheme does).
TEST(NestedOpenSides, SidesWalledOutsideTheJet)
{
  Flow flow;
  flow.swirl = 0.0;
  flow.walled = true;
  convergence(flow, "traction sides walled outside the jet", {8, 16, 32}, 1.5);
}

TEST(NestedOpenSides, OneRankAndTwoRanksAgree)
{
  const Result world = run(PETSC_COMM_WORLD, 8, Flow{}, true);
  const Result self = run(PETSC_COMM_SELF, 8, Flow{}, true);
  ASSERT_EQ(world.u.size(), self.u.size());
  double difference = 0.0, size = 0.0;
  for (std::size_t i = 0; i < self.u.size(); ++i) {
    difference = std::max(difference, std::abs(world.u[i] - self.u[i]));
    size = std::max(size, std::abs(self.u[i]));
  }
  report("1 rank vs all ranks: max difference %.2e (max |u| %.2f)\n", difference, size);
  EXPECT_LT(difference, 1e-9 * size);
}

} // namespace
} // namespace ibvalve::fluid
