// A flexible plate clamped to the bottom wall of a channel flow bends under the fluid load; at the
// coupled steady state its tip deflection must be what a quasi-static FE solve of the same plate
// (same law, same clamp) predicts under the fluid load MEASURED FROM THE FLUID, within 10 %.
//
// 2-D-like: the plate spans the periodic z extent, so flow and plate are uniform in z and the plate
// is in plane strain (the periodic fluid keeps u_z = 0). The load on each horizontal strip of the
// plate is the momentum balance of a control box around that strip,
//   F_k = oint_{box} (sigma - rho u (x) u) n . e_x dA,   sigma = -p I + mu (grad u + grad u^T),
// evaluated from the fluid's pressure and velocity three grid cells away from the plate (beyond the
// kernel's reach) and applied as a dead traction on the plate's upstream face.
//
// Why not the structure's own nodal forces: the load -F(u_IB) would give back u_IB in the FE solve
// by construction, a comparison that could not fail. The control-box load is independent of the
// structure's forces; the two deflections agree only when the coupled system is in equilibrium, the
// spread force reaches the fluid where the structure is and the structure moves with the fluid.
//
// The prediction is the FE solve on a mesh refined 4 times beyond the IB plate's mesh: the IB plate
// is kept nearly isochoric by the fluid (the fluid pressure takes the volumetric forces), so it does
// not lock like the trilinear FE solve with a volumetric penalty does on the same coarse mesh; the
// deflections on the IB mesh and on the refined meshes are printed.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <gtest/gtest.h>

#include "fe/loads.hpp"
#include "fe/mesh.hpp"
#include "fe/quasi_static.hpp"
#include "fluid/queries.hpp"
#include "ibfe_cases.hpp"
#include "io/petsc_check.hpp"

using namespace ibvalve;
using namespace ibvalve::ib::testing;

namespace {

// Channel y in [0, H] (no-slip walls), x in [0, 2H] (Poiseuille inflow at x = 0 with mean speed U,
// zero-traction outlet at x = 2H), periodic z of four cells. Reynolds number rho U H / mu = 1.
constexpr double H = 1.0, U = 1.0, mu = 1.0;
constexpr double rho = 1.0;
// The plate: x in [x_c - t/2, x_c + t/2], y in [y0, y0 + L], the whole z extent; neo-Hookean with a
// volumetric penalty (the same law in the IB run and in the FE solves).
constexpr double x_c = 1.0, L = 0.5;
constexpr int strips = 8; // control boxes over the plate's height

struct FlapSettings {
  int cells = 16; // grid cells across the channel
  double thickness = 0.25;
  std::array<int, 2> elements{4, 8}; // across the thickness, along the height (a multiple of `strips`)
  double mu_s = 8e4;                 // shear modulus, dyn/cm^2
  double kappa_ratio = 10.0;         // volumetric penalty / shear modulus (Poisson ratio 0.45)
  int steps = 1500;
  double dt_factor = 2.0;                   // time step / the stability estimate
  std::vector<int> fe_refinements{1, 2, 4}; // FE meshes: the IB plate's mesh, then refined
};

struct FlapResult {
  double ib_tip = 0.0;
  std::vector<double> fe_tips;
  double base = 0.0;        // largest base displacement in the IB run (held by the tether)
  double last_change = 0.0; // relative change of the tip deflection over the last tenth of the run
  double total_load = 0.0;  // sum of the strip forces
};

// The plate's mesh (one element in z per `nz`); its base sits a quarter cell above the wall, so the
// structure's points never touch the box side.
fe::Mesh plate_mesh(const FlapSettings& s, double y0, double Lz, int refinement, int nz)
{
  return fe::box_mesh(fe::CellShape::hexahedron, fe::Vec3(x_c - 0.5 * s.thickness, y0, 0.0),
                      fe::Vec3(x_c + 0.5 * s.thickness, y0 + L, Lz),
                      {refinement * s.elements[0], refinement * s.elements[1], nz});
}

double poiseuille(double y)
{
  return 6.0 * U * y * (H - y) / (H * H);
}

// The x-component of (sigma - rho u u) n integrated over the sides of the box [x1, x2] x [ya, yb] per
// unit z-width, sampled in the plane z (the flow is uniform in z): the fluid's x-force on the box's
// contents. Midpoint rule with spacing h/4; derivatives by central differences of step h/2 of the
// trilinearly interpolated velocity.
double box_x_force(const fluid::NavierStokes& f, double x1, double x2, double ya, double yb, double z)
{
  const double h = f.grid().box().spacing(0), d = 0.5 * h;
  auto u = [&](double x, double y) { return fluid::velocity_at(f, {x, y, z}); };
  auto sxx = [&](double x, double y) { // sigma_xx - rho u u
    const double ux = (u(x + d, y)[0] - u(x - d, y)[0]) / (2.0 * d);
    const fluid::Real3 v = u(x, y);
    return -fluid::pressure_at(f, {x, y, z}) + 2.0 * mu * ux - rho * v[0] * v[0];
  };
  auto sxy = [&](double x, double y) { // sigma_xy - rho u v
    const double uy = (u(x, y + d)[0] - u(x, y - d)[0]) / (2.0 * d);
    const double vx = (u(x + d, y)[1] - u(x - d, y)[1]) / (2.0 * d);
    const fluid::Real3 v = u(x, y);
    return mu * (uy + vx) - rho * v[0] * v[1];
  };
  double force = 0.0;
  const int ny = std::max(1, static_cast<int>(std::lround((yb - ya) / (0.25 * h))));
  for (int i = 0; i < ny; ++i) {
    const double y = ya + (i + 0.5) * (yb - ya) / ny;
    force += (sxx(x2, y) - sxx(x1, y)) * (yb - ya) / ny;
  }
  const int nx = std::max(1, static_cast<int>(std::lround((x2 - x1) / (0.25 * h))));
  for (int i = 0; i < nx; ++i) {
    const double x = x1 + (i + 0.5) * (x2 - x1) / nx;
    force += (sxy(x, yb) - sxy(x, ya)) * (x2 - x1) / nx;
  }
  return force;
}

// The same plate quasi-statically on a mesh `refinement` times finer: plane strain (u_z = 0, as the
// periodic flow keeps it), the base where `base_fit` puts it, the strip tractions on the upstream face.
double quasi_static_tip(const FlapSettings& s, int refinement, double y0, double Lz,
                        const std::vector<double>& traction, const Eigen::Matrix<double, 2, 3>& base_fit);

double mean_tip(const fe::Mesh& mesh, const std::vector<double>& u)
{
  const auto& top = mesh.group("ymax").nodes;
  double sum = 0.0;
  for (int n : top) sum += u[3 * n];
  return sum / static_cast<double>(top.size());
}

double quasi_static_tip(const FlapSettings& s, int refinement, double y0, double Lz,
                        const std::vector<double>& traction, const Eigen::Matrix<double, 2, 3>& base_fit)
{
  // Plane strain with u_z = 0 everywhere: one element in z is exact.
  const fe::Mesh mesh = plate_mesh(s, y0, Lz, refinement, 1);
  const fe::SolidModel solid(mesh, one_part(mesh, neo_hookean(s.mu_s, s.kappa_ratio * s.mu_s)), 2,
                             PETSC_COMM_WORLD);
  const std::vector<double> load = fe::surface_traction_load(
      mesh, "xmin",
      [&](const fe::Vec3& X) {
        const int k = std::clamp(static_cast<int>((X[1] - y0) / (L / strips)), 0, strips - 1);
        return fe::Vec3(traction[k], 0.0, 0.0);
      },
      4, PETSC_COMM_WORLD);
  const auto& base_nodes = mesh.group("ymin").nodes;
  fe::DirichletCondition base;
  base.nodes = base_nodes;
  base.displacement = [base_fit](const fe::Vec3& X) {
    const Eigen::Vector2d phi(1.0, X[0] - x_c);
    return fe::Vec3(base_fit.transpose() * phi);
  };
  fe::DirichletCondition plane;
  for (std::size_t n = 0; n < mesh.num_nodes(); ++n)
    if (!std::binary_search(base_nodes.begin(), base_nodes.end(), static_cast<int>(n)))
      plane.nodes.push_back(static_cast<int>(n));
  plane.components = {false, false, true};
  fe::QuasiStaticOptions options;
  options.load_steps = 2;
  // Newton's full steps: the nearly incompressible plate's first update overshoots in residual, where
  // the backtracking line search stalls; the full steps converge quadratically.
  options.prefix = "flap_fe_";
  PETSC_CHECK(PetscOptionsSetValue(nullptr, "-flap_fe_snes_linesearch_type", "basic"));
  options.relative_tolerance = 1e-9;
  options.absolute_tolerance = 1e-7;
  fe::QuasiStaticSolver solver(solid, {base, plane}, load, options);
  return mean_tip(mesh, solver.solve().displacement);
}

FlapResult run_flap(const FlapSettings& s)
{
  const double h = H / s.cells, Lz = 4.0 * h, y0 = 0.25 * h;
  fluid::BoxGeometry box;
  box.upper = {2.0 * H, H, Lz};
  box.cells = {2 * s.cells, s.cells, 4};
  box.periodic = {false, false, true};
  fluid::BoundaryConditions bc;
  bc.side(0, 0).kind = fluid::SideKind::velocity;
  bc.side(0, 0).velocity = [](const fluid::Real3& x, double) {
    return fluid::Real3{poiseuille(x[1]), 0.0, 0.0};
  };
  bc.side(0, 1).kind = fluid::SideKind::traction;
  bc.side(1, 0).kind = fluid::SideKind::velocity;
  bc.side(1, 1).kind = fluid::SideKind::velocity;
  fluid::FluidSettings fs;
  fs.rho = rho;
  fs.mu = mu;
  fs.solver = fluid::SolverKind::krylov;
  fs.rtol = 1e-10;
  fluid::NavierStokes fluid(PETSC_COMM_WORLD, box, bc, fs);
  // Start from the undisturbed channel flow; the plate then loads up and bends.
  fluid.set_initial_condition(
      [](const fluid::Real3& x, double) {
        return fluid::Real3{poiseuille(x[1]), 0.0, 0.0};
      },
      [](const fluid::Real3& x, double) { return 12.0 * mu * U / (H * H) * (2.0 * H - x[0]); }, 0.0);

  // Four elements in z, one per grid cell, so the coupling-point rules stay small.
  const fe::Mesh mesh = plate_mesh(s, y0, Lz, 1, 4);
  fe::SolidModel solid(mesh, one_part(mesh, neo_hookean(s.mu_s, s.kappa_ratio * s.mu_s)), 2,
                       PETSC_COMM_WORLD);
  // The clamp: the base face tethered to its reference position (a stiff spring per unit area).
  ib::IbfeSettings settings;
  settings.tethers.push_back({"ymin", 50.0 * s.mu_s / h, 0.0});
  ib::IbfeIntegrator ibfe(fluid, solid, settings);
  const double dt = s.dt_factor * ibfe.stability_estimate().dt;
  if (is_root())
    std::printf("flap %d cells across: dt = %.3g s (estimate %.3g)\n", s.cells, dt,
                ibfe.stability_estimate().dt);

  std::vector<double> history;
  for (int n = 0; n < s.steps; ++n) {
    ibfe.step(dt);
    history.push_back(mean_tip(mesh, ibfe.displacement()));
    if (is_root() && (n + 1) % (s.steps / 10) == 0)
      std::printf("  step %d t = %.4f s: tip deflection %.5g cm\n", n + 1, ibfe.time(), history.back());
  }
  FlapResult r;
  r.ib_tip = history.back();
  r.last_change = std::abs(history.back() - history[history.size() * 9 / 10]) / std::abs(history.back());
  for (int n : mesh.group("ymin").nodes)
    for (int d = 0; d < 3; ++d) r.base = std::max(r.base, std::abs(ibfe.displacement()[3 * n + d]));

  // The fluid load per strip from control boxes reaching 3 grid cells beyond the deformed plate.
  double x_min = 1e30, x_max = -1e30;
  for (const auto& p : ibfe.positions()) {
    x_min = std::min(x_min, p[0]);
    x_max = std::max(x_max, p[0]);
  }
  const double x1 = x_min - 3.0 * h, x2 = x_max + 3.0 * h, z = 0.5 * Lz;
  // Strip k >= 1 is the plate between y = k L/8 and (k+1) L/8; the top box reaches 3 cells over the
  // plate's end, so it also takes the load on the top face.
  std::vector<double> traction(strips, 0.0);
  for (int k = 1; k < strips; ++k) {
    const double ya = y0 + k * L / strips, yb = y0 + (k + 1 < strips ? (k + 1) * L / strips : L + 3.0 * h);
    const double F = box_x_force(fluid, x1, x2, ya, yb, z); // per unit z-width
    traction[k] = F / (L / strips);                         // per unit area of the upstream face
    r.total_load += F * Lz;
    if (is_root()) std::printf("  strip y in [%.4f, %.4f]: load %.5g dyn/cm\n", ya, yb, F);
  }
  // The lowest strip (y < y0 + L/8), next to the wall and the tethered base, gets no load: its share
  // of a uniform load makes 0.25 % of a cantilever's tip deflection.

  // The base as the tether held it, u(X) = a + b (X_x - x_c) per component (least squares over the
  // base nodes: a translation plus the rotation of the base face).
  const auto& base_nodes = mesh.group("ymin").nodes;
  Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
  Eigen::Matrix<double, 2, 3> rhs = Eigen::Matrix<double, 2, 3>::Zero();
  for (int n : base_nodes) {
    const Eigen::Vector2d phi(1.0, mesh.nodes()[n][0] - x_c);
    normal += phi * phi.transpose();
    for (int d = 0; d < 3; ++d) rhs.col(d) += phi * ibfe.displacement()[3 * n + d];
  }
  const Eigen::Matrix<double, 2, 3> base_fit = normal.ldlt().solve(rhs);
  for (int refinement : s.fe_refinements) {
    const double tip = quasi_static_tip(s, refinement, y0, Lz, traction, base_fit);
    r.fe_tips.push_back(tip);
    if (is_root())
      std::printf("  FE solve, mesh %d x %d elements: tip %.5g cm\n", refinement * s.elements[0],
                  refinement * s.elements[1], tip);
  }
  return r;
}

// Checks the run reached its steady state and compares the IB tip deflection with the FE prediction.
void expect_flap_agrees(const FlapSettings& s)
{
  const FlapResult r = run_flap(s);
  const auto& f = r.fe_tips; // meshes refined 1, 2, 4 times
  // The FE sequence converges geometrically (locking fades with refinement): Aitken's extrapolation
  // f_3 + (f_3 - f_2)^2 / ((f_2 - f_1) - (f_3 - f_2)) estimates the converged deflection.
  const double extrapolated = f[2] + (f[2] - f[1]) * (f[2] - f[1]) / ((f[1] - f[0]) - (f[2] - f[1]));
  auto difference = [&](double fe) { return std::abs(r.ib_tip - fe) / std::abs(fe); };
  if (is_root())
    std::printf("flap (%d cells across, plate %.3g cm thick): IB tip deflection %.5g cm; FE prediction "
                "(finest mesh) %.5g cm, relative difference %.3g; extrapolated FE %.5g cm (difference %.3g); "
                "FE on the IB plate's own mesh %.5g cm (difference %.3g); base held within %.3g cm; change "
                "over the last tenth %.3g; total load %.5g dyn\n",
                s.cells, s.thickness, r.ib_tip, f[2], difference(f[2]), extrapolated,
                difference(extrapolated), f[0], difference(f[0]), r.base, r.last_change, r.total_load);
  EXPECT_LT(r.last_change, 0.01) << "not at a steady state";
  EXPECT_LT(difference(f[2]), 0.10);
  EXPECT_LT(difference(extrapolated), 0.10);
}

} // namespace

TEST(FlexibleFlap, BendsAsTheQuasiStaticSolveUnderTheMeasuredFluidLoadPredicts)
{
  // The plate 4 grid cells thick (16 cells across the channel), elements of one grid cell.
  expect_flap_agrees(FlapSettings{});
}

TEST(FlexibleFlap, NightlyOnTheGridTwiceAsFine)
{
  // The same plate on 32 cells across the channel (8 cells thick), elements of one grid cell; the
  // time step halves with the grid, so twice as many steps reach the same time.
  FlapSettings s;
  s.cells = 32;
  s.elements = {8, 16};
  s.steps = 3000;
  expect_flap_agrees(s);
}
