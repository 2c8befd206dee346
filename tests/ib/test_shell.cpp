// A thick elastic spherical shell, held inflated (r^3 = R^3 + a, an isochoric state) in fluid at rest,
// stays at rest with the pressure jump of the thick-walled analytic solution between its inside and
// its outside: the spread elastic force is balanced by the fluid pressure alone.
#include <cstdlib>

#include <gtest/gtest.h>

#include "fe/shell_mesh.hpp"
#include "ibfe_cases.hpp"

using namespace ibvalve;
using namespace ibvalve::ib::testing;

namespace {

struct ShellResult {
  double measured = 0.0, analytic = 0.0, max_velocity = 0.0;
};

ShellResult run_shell(int cells, int n, int layers, int steps, double dt, ib::KernelKind kernel)
{
  const double mu_solid = 100.0, R_i = 0.2, R_o = 0.3, a = 0.22 * 0.22 * 0.22 - R_i * R_i * R_i;
  const ib::Vec3 c(0.5, 0.5, 0.5);
  auto fluid = periodic_fluid(PETSC_COMM_WORLD, cells, 1.0, 0.1);
  const fe::Mesh mesh = fe::spherical_shell_mesh(c, R_i, R_o, n, layers);
  fe::SolidModel solid(mesh, one_part(mesh, neo_hookean(mu_solid, 10.0 * mu_solid)), 2, PETSC_COMM_WORLD);
  ib::IbfeSettings settings;
  settings.kernel = kernel;
  ib::IbfeIntegrator ibfe(*fluid, solid, settings);
  std::vector<double> u(solid.num_dofs());
  for (std::size_t node = 0; node < mesh.num_nodes(); ++node) {
    const ib::Vec3 X = mesh.nodes()[node] - c;
    const double R = X.norm(), r = std::cbrt(R * R * R + a);
    for (int d = 0; d < 3; ++d) u[3 * node + d] = (r / R - 1.0) * X[d];
  }
  ibfe.set_displacement(u);
  for (int s = 0; s < steps; ++s) ibfe.step(dt);
  ShellResult result;
  const double inside = 0.5 * R_i, outside = R_o + 0.1;
  auto distance = [&](const fluid::Real3& x) { return std::hypot(x[0] - c[0], x[1] - c[1], x[2] - c[2]); };
  result.measured = mean_pressure(*fluid, [&](const fluid::Real3& x) { return distance(x) < inside; }) -
                    mean_pressure(*fluid, [&](const fluid::Real3& x) { return distance(x) > outside; });
  result.analytic = shell_pressure_jump(mu_solid, R_i, R_o, a);
  for (double v : ibfe.velocity()) result.max_velocity = std::max(result.max_velocity, std::abs(v));
  const ib::IbfeTimings& t = ibfe.timings();
  if (is_root())
    std::printf(
        "%zu coupling points; per step: total %.3g s, fluid %.3g, interpolation %.3g, projection %.3g, "
        "force %.3g, "
        "spreading %.3g, points %.3g\n",
        ibfe.coupling_point_count(), t.total / t.steps, t.fluid / t.steps, t.interpolation / t.steps,
        t.projection / t.steps, t.force / t.steps, t.spreading / t.steps, t.points / t.steps);
  return result;
}

} // namespace

TEST(PressurizedShell, HoldsTheThickWalledPressureJumpWithinFivePercent)
{
  const ShellResult r = run_shell(32, 8, 3, 20, 1e-3, ib::default_kernel);
  const double error = std::abs(r.measured - r.analytic) / r.analytic;
  if (is_root())
    std::printf("shell 32^3: measured %.4f, analytic %.4f dyn/cm^2, relative error %.4f, max |U| %.3g cm/s\n",
                r.measured, r.analytic, error, r.max_velocity);
  EXPECT_LT(error, 0.05);
}

TEST(PressurizedShellNightly, IsCloserOnAFinerGrid)
{
  const ShellResult coarse = run_shell(32, 8, 3, 20, 1e-3, ib::default_kernel);
  const ShellResult fine = run_shell(48, 12, 5, 30, 2.0 / 3.0 * 1e-3, ib::default_kernel);
  const double e_coarse = std::abs(coarse.measured - coarse.analytic) / coarse.analytic;
  const double e_fine = std::abs(fine.measured - fine.analytic) / fine.analytic;
  if (is_root()) std::printf("shell: relative error %.4f on 32^3, %.4f on 48^3\n", e_coarse, e_fine);
  EXPECT_LT(e_fine, e_coarse);
}

TEST(PressurizedShellNightly, EveryKernelHoldsThePressureJump)
{
  for (ib::KernelKind kind : {ib::KernelKind::piecewise_linear, ib::KernelKind::ib_3, ib::KernelKind::ib_4,
                              ib::KernelKind::ib_6, ib::KernelKind::bspline_3}) {
    const ShellResult r = run_shell(32, 8, 3, 20, 1e-3, kind);
    const double error = std::abs(r.measured - r.analytic) / r.analytic;
    if (is_root())
      std::printf("shell 32^3, %s kernel: measured %.4f vs %.4f dyn/cm^2, relative error %.4f\n",
                  ib::kernel_name(kind).c_str(), r.measured, r.analytic, error);
    EXPECT_LT(error, 0.05) << ib::kernel_name(kind);
  }
}
