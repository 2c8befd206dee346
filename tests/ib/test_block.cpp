// A stretched elastic block released in fluid at rest in a periodic box: it relaxes towards its
// reference shape, its volume stays within 1 % (the discrete fluid velocity is divergence free and
// the structure follows it), and the total momentum of fluid + structure stays zero (the internal
// forces sum to zero and spreading conserves the total force). The same run on 1 and on 2 ranks
// agrees to solver tolerance over 20 coupled steps.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "base/errors.hpp"
#include "fe/mesh.hpp"
#include "ibfe_cases.hpp"

using namespace ibvalve;
using namespace ibvalve::ib::testing;

namespace {

constexpr double stretch = 1.25;

fe::Mesh block_mesh()
{
  return fe::box_mesh(fe::CellShape::hexahedron, fe::Vec3(0.35, 0.4, 0.4), fe::Vec3(0.65, 0.6, 0.6),
                      {6, 4, 4});
}

// Isochoric stretch about the block's centre: x by `stretch`, y and z by 1/sqrt(stretch).
std::vector<double> stretched(const fe::Mesh& mesh)
{
  const fe::Vec3 c(0.5, 0.5, 0.5);
  const fe::Vec3 factor(stretch, 1.0 / std::sqrt(stretch), 1.0 / std::sqrt(stretch));
  std::vector<double> u(3 * mesh.num_nodes());
  for (std::size_t n = 0; n < mesh.num_nodes(); ++n)
    for (int d = 0; d < 3; ++d) u[3 * n + d] = (factor[d] - 1.0) * (mesh.nodes()[n][d] - c[d]);
  return u;
}

// Largest distance of a node from where the reference shape, moved with the block's mean
// displacement, puts it.
double shape_deviation(const std::vector<double>& u)
{
  const std::size_t nodes = u.size() / 3;
  ib::Vec3 mean = ib::Vec3::Zero();
  for (std::size_t n = 0; n < nodes; ++n) mean += ib::Vec3(u[3 * n], u[3 * n + 1], u[3 * n + 2]);
  mean /= static_cast<double>(nodes);
  double worst = 0.0;
  for (std::size_t n = 0; n < nodes; ++n)
    worst = std::max(worst, (ib::Vec3(u[3 * n], u[3 * n + 1], u[3 * n + 2]) - mean).norm());
  return worst;
}

struct BlockRun {
  std::unique_ptr<fluid::NavierStokes> fluid;
  fe::Mesh mesh = block_mesh();
  std::unique_ptr<fe::SolidModel> solid;
  std::unique_ptr<ib::IbfeIntegrator> ibfe;

  BlockRun(MPI_Comm comm, int cells, fe::MassKind projection, double viscosity = 0.1)
  {
    fluid = periodic_fluid(comm, cells, 1.0, viscosity);
    solid = std::make_unique<fe::SolidModel>(mesh, one_part(mesh, neo_hookean(100.0, 1000.0)), 2, comm);
    ib::IbfeSettings settings;
    settings.velocity_projection = settings.force_projection = projection;
    ibfe = std::make_unique<ib::IbfeIntegrator>(*fluid, *solid, settings);
    ibfe->set_displacement(stretched(mesh));
  }
};

} // namespace

TEST(StretchedBlock, RelaxesWithVolumeWithinOnePercentAndZeroMomentum)
{
  // The consistent projection is exact for linear velocity fields, the lumped one only for constant
  // fields (first order), so the structure follows the divergence-free flow less closely with it: on
  // this coarse mesh (elements 0.8 grid cells) it loses about 1.2 % of volume over the run, and the
  // block cannot return to its reference shape any closer than that volume error allows.
  struct Case {
    fe::MassKind projection;
    double volume_tolerance, relaxed_fraction;
  };
  for (const Case& c : {Case{fe::MassKind::consistent, 0.01, 0.1}, Case{fe::MassKind::lumped, 0.015, 0.3}}) {
    const fe::MassKind projection = c.projection;
    BlockRun run(PETSC_COMM_WORLD, 16, projection);
    const double V0 = run.mesh.volume();
    const double initial_deviation = shape_deviation(run.ibfe->displacement());
    double worst_volume = 0.0, worst_momentum = 0.0, momentum_scale = 0.0;
    const double dt = 2e-3;
    for (int s = 0; s < 150; ++s) {
      run.ibfe->step(dt);
      worst_volume = std::max(worst_volume, std::abs(run.ibfe->volume() / V0 - 1.0));
      // Momentum of the fluid (the structure has no mass of its own in this IB formulation).
      worst_momentum = std::max(worst_momentum, fluid_momentum(*run.fluid).norm());
      double speed = 0.0;
      for (double v : run.ibfe->velocity()) speed = std::max(speed, std::abs(v));
      momentum_scale = std::max(momentum_scale, speed * V0);
    }
    const double final_deviation = shape_deviation(run.ibfe->displacement());
    if (is_root())
      std::printf(
          "%s projection: shape deviation %.4g -> %.4g cm, max |V/V0 - 1| = %.3g, max |momentum| = %.3g "
          "(scale %.3g)\n",
          projection == fe::MassKind::consistent ? "consistent" : "lumped", initial_deviation,
          final_deviation, worst_volume, worst_momentum, momentum_scale);
    EXPECT_LT(final_deviation, c.relaxed_fraction * initial_deviation);
    EXPECT_LT(worst_volume, c.volume_tolerance);
    EXPECT_LT(worst_momentum, 1e-12 * momentum_scale);
  }
}

TEST(StretchedBlock, OneRankAndAllRanksAgreeOverTwentySteps)
{
  int size = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  BlockRun distributed(PETSC_COMM_WORLD, 16, fe::MassKind::consistent);
  BlockRun serial(PETSC_COMM_SELF, 16, fe::MassKind::consistent);
  for (int s = 0; s < 20; ++s) {
    distributed.ibfe->step(2e-3);
    serial.ibfe->step(2e-3);
  }
  const auto& a = distributed.ibfe->displacement();
  const auto& b = serial.ibfe->displacement();
  double difference = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    difference = std::max(difference, std::abs(a[i] - b[i]));
    scale = std::max(scale, std::abs(b[i]));
  }
  if (is_root())
    std::printf(
        "%d ranks vs 1 rank after 20 steps: max displacement difference %.3g (max displacement %.3g)\n", size,
        difference, scale);
  EXPECT_LT(difference, 1e-10 * scale);
}

TEST(StretchedBlock, TheCoupledSchemeIsSecondOrderInTime)
{
  // The structure's displacement at t = 0.032 s with dt, dt/2, dt/4 against dt/8: the error ratios
  // between successive halvings approach 4 for a second-order scheme.
  const double T = 0.032;
  std::vector<std::vector<double>> results;
  for (int steps : {8, 16, 32, 64}) {
    BlockRun run(PETSC_COMM_WORLD, 16, fe::MassKind::consistent);
    for (int s = 0; s < steps; ++s) run.ibfe->step(T / steps);
    results.push_back(run.ibfe->displacement());
  }
  std::vector<double> errors;
  for (std::size_t r = 0; r + 1 < results.size(); ++r) {
    double e = 0.0;
    for (std::size_t i = 0; i < results[r].size(); ++i)
      e = std::max(e, std::abs(results[r][i] - results.back()[i]));
    errors.push_back(e);
  }
  // With a reference at dt/8 the errors e_k ~ C dt_k^2 (1 - 1/64 ...): the ratio of the first two is
  // (1 - 1/16) / (1/4 - 1/16) * ... ~ 5; require an observed order above 1.8.
  const double order = std::log2((errors[0] - errors[1]) / (errors[1] - errors[2]));
  if (is_root())
    std::printf("time convergence: errors %.3g %.3g %.3g against dt/8; observed order %.2f\n", errors[0],
                errors[1], errors[2], order);
  EXPECT_GT(order, 1.8);
}

TEST(Tethers, PullATranslatedBlockBackWhileAnUntetheredOneStays)
{
  // A rigid translation stores no elastic energy: without a tether the block does not move. A volume
  // tether with stiffness kappa pulls it back (F_a = -kappa w_a u_a).
  for (double stiffness : {0.0, 2e4}) {
    auto fluid = periodic_fluid(PETSC_COMM_WORLD, 16, 1.0, 0.1);
    const fe::Mesh mesh = block_mesh();
    fe::SolidModel solid(mesh, one_part(mesh, neo_hookean(100.0, 1000.0)), 2, PETSC_COMM_WORLD);
    ib::IbfeSettings settings;
    settings.tethers.push_back({"body", stiffness, 0.0});
    ib::IbfeIntegrator ibfe(*fluid, solid, settings);
    std::vector<double> u(solid.num_dofs());
    for (std::size_t n = 0; n < mesh.num_nodes(); ++n) u[3 * n] = 0.05;
    ibfe.set_displacement(u);
    for (int s = 0; s < 40; ++s) ibfe.step(1e-3);
    double mean = 0.0, speed = 0.0;
    for (std::size_t n = 0; n < mesh.num_nodes(); ++n) mean += ibfe.displacement()[3 * n] / mesh.num_nodes();
    for (double v : ibfe.velocity()) speed = std::max(speed, std::abs(v));
    if (is_root())
      std::printf("tether stiffness %g: mean x displacement 0.05 -> %.4g, max |U| %.3g\n", stiffness, mean,
                  speed);
    if (stiffness == 0.0) {
      EXPECT_NEAR(mean, 0.05, 1e-12);
      EXPECT_LT(speed, 1e-12);
    } else {
      EXPECT_LT(mean, 0.025);
    }
  }
}

TEST(Stability, TheEstimateSeparatesStableFromBlowingUpSteps)
{
  // The logged estimate is a safe step: at 1/2 and 1 times it the block relaxes quietly. It is
  // conservative (the kernel smooths the stiffest modes away; on this case the scheme holds up to
  // between 4 and 8 times the estimate), but not wildly so: at 16 times it the run blows up and
  // stops with a RunError (a non-finite structure position) instead of carrying NaNs on.
  for (double factor : {0.5, 1.0, 16.0}) {
    BlockRun run(PETSC_COMM_WORLD, 16, fe::MassKind::consistent);
    const double dt = factor * run.ibfe->stability_estimate().dt;
    bool failed = false;
    double largest = 0.0;
    try {
      for (int s = 0; s < 100; ++s) {
        run.ibfe->step(dt);
        for (double u : run.ibfe->displacement()) largest = std::max(largest, std::abs(u));
        if (largest > 10.0) break; // far outside anything physical: count it as blown up
      }
    } catch (const RunError&) {
      failed = true;
    }
    if (is_root())
      std::printf("dt = %.2f x estimate: %s (largest displacement %.3g)\n", factor,
                  failed ? "RunError" : "completed", largest);
    if (factor <= 1.0) {
      EXPECT_FALSE(failed);
      EXPECT_LT(largest, 0.05);
    } else {
      EXPECT_TRUE(failed || largest > 10.0);
    }
  }
}

TEST(Stability, TheEstimateAddsTheStiffestPartToTheStiffestTetherAndNamesEachSource)
{
  // A neo-Hookean block (mu = 100 dyn/cm^2) with a volume tether: at F = I the isochoric modulus is
  // E = 2 mu (dP/dF = mu (dF + dF^T) + lambda tr(dF) I, whose symmetric trace-free eigenvalue is 2 mu),
  // so the part's omega^2 is 12 (2 mu) / (rho h^2); the tether's is kappa w / (rho h^3) with w the
  // weight int N_a dX of an interior node, the volume of one 0.05 cm cube element.
  constexpr double mu = 100.0, kappa = 2e4, rho = 1.0, viscosity = 0.1;
  auto fluid = periodic_fluid(PETSC_COMM_WORLD, 16, rho, viscosity);
  const fe::Mesh mesh = block_mesh();
  fe::SolidModel solid(mesh, one_part(mesh, neo_hookean(mu, 1000.0)), 2, PETSC_COMM_WORLD);
  ib::IbfeSettings settings;
  settings.tethers.push_back({"body", kappa, 0.0});
  const ib::IbfeIntegrator ibfe(*fluid, solid, settings);
  const ib::StabilityEstimate s = ibfe.stability_estimate();
  const double h = 1.0 / 16.0; // the grid spacing: larger than the smallest edge, 0.05 cm
  EXPECT_DOUBLE_EQ(s.length, h);
  EXPECT_NEAR(s.modulus, 2.0 * mu, 1e-12 * mu);
  const double part = 12.0 * 2.0 * mu / (rho * h * h),
               tether = kappa * 0.05 * 0.05 * 0.05 / (rho * h * h * h);
  ASSERT_EQ(s.terms.size(), 2u);
  // Largest first: here the part.
  EXPECT_EQ(s.terms[0].source, "part body");
  EXPECT_EQ(s.terms[1].source, "tether body");
  EXPECT_NEAR(s.terms[0].omega2, part, 1e-12 * part);
  EXPECT_NEAR(s.terms[1].omega2, tether, 1e-9 * tether);
  EXPECT_NEAR(s.inertial_dt, 2.0 / std::sqrt(part + tether), 1e-12 * s.inertial_dt);
  const double gamma = 12.0 * viscosity / (rho * h * h);
  for (const auto& term : s.terms) {
    const double alone = std::max(2.0 / std::sqrt(term.omega2), 2.0 * gamma / term.omega2);
    EXPECT_NEAR(term.dt, alone, 1e-12 * alone) << term.source;
    EXPECT_GT(term.dt, s.dt) << term.source; // each alone allows more than both together
  }
  // The reference state and a zero displacement are the same state.
  const std::vector<double> zero(solid.num_dofs(), 0.0);
  EXPECT_DOUBLE_EQ(ibfe.stability_estimate(zero).dt, s.dt);
  EXPECT_NE(ib::describe_stability_terms(s).find("part body "), std::string::npos);
}

TEST(Stability, AnExponentialFiberLawStretchedAlongItsFibersLowersTheEstimate)
{
  // A W3 block (C1 = 100 dyn/cm^2, a = 500 dyn/cm^2, b = 50), fibers along x, stretched isochorically
  // along them by 1.05, 1.1 and 1.15: the fiber term's stiffness grows like exp(b (I4 - 1)^2), so the
  // modulus rises and the estimate falls with the stretch; the deformation is homogeneous, so every
  // element's own limit (stable_step in the fields) is the part's.
  auto fluid = periodic_fluid(PETSC_COMM_WORLD, 16, 1.0, 0.1);
  const fe::Mesh mesh = block_mesh();
  auto law = std::make_shared<materials::InvariantLaw>(materials::LawKind::W3,
                                                       std::vector<double>{100.0, 500.0, 50.0});
  fe::SolidModel solid(mesh, one_part(mesh, law), 2, PETSC_COMM_WORLD);
  solid.set_fibers(std::vector<materials::FiberFrame>(
      mesh.num_elements(), materials::FiberFrame{materials::Vec3::UnitX(), materials::Vec3::Zero()}));
  const ib::IbfeIntegrator ibfe(*fluid, solid, ib::IbfeSettings{});
  double previous_modulus = ibfe.stability_estimate().modulus, previous_dt = ibfe.stability_estimate().dt;
  for (double lambda : {1.05, 1.1, 1.15}) {
    std::vector<double> u(solid.num_dofs());
    const fe::Vec3 factor(lambda, 1.0 / std::sqrt(lambda), 1.0 / std::sqrt(lambda));
    for (std::size_t n = 0; n < mesh.num_nodes(); ++n)
      for (int d = 0; d < 3; ++d) u[3 * n + d] = (factor[d] - 1.0) * (mesh.nodes()[n][d] - 0.5);
    const ib::StabilityEstimate s = ibfe.stability_estimate(u);
    if (is_root())
      std::printf("fiber stretch %.2f: modulus %.4g dyn/cm^2, estimate %.4g s\n", lambda, s.modulus, s.dt);
    EXPECT_GT(s.modulus, previous_modulus) << lambda;
    EXPECT_LT(s.dt, previous_dt) << lambda;
    for (double step : ibfe.element_stable_steps(u)) EXPECT_NEAR(step, s.terms.front().dt, 1e-9 * step);
    previous_modulus = s.modulus;
    previous_dt = s.dt;
  }
}

TEST(WalledBox, TheBlockRelaxesWithItsVolumeKeptAndLeavingTheBoxIsARunError)
{
  // No-slip walls on every side (Krylov Stokes solver): the same relaxation, volume within 1 %.
  fluid::BoxGeometry box;
  box.cells = {16, 16, 16};
  box.periodic = {false, false, false};
  fluid::BoundaryConditions bc;
  for (int s = 0; s < 6; ++s) bc.side(s).kind = fluid::SideKind::velocity;
  fluid::FluidSettings settings;
  settings.solver = fluid::SolverKind::krylov;
  settings.mu = 0.1;
  fluid::NavierStokes fluid(PETSC_COMM_WORLD, box, bc, settings);
  fluid.set_initial_condition(
      [](const fluid::Real3&, double) {
        return fluid::Real3{0, 0, 0};
      },
      nullptr, 0.0);
  const fe::Mesh mesh = block_mesh();
  fe::SolidModel solid(mesh, one_part(mesh, neo_hookean(100.0, 1000.0)), 2, PETSC_COMM_WORLD);
  ib::IbfeIntegrator ibfe(fluid, solid, {});
  ibfe.set_displacement(stretched(mesh));
  const double V0 = mesh.volume(), initial = shape_deviation(ibfe.displacement());
  double worst_volume = 0.0;
  for (int s = 0; s < 60; ++s) {
    ibfe.step(2e-3);
    worst_volume = std::max(worst_volume, std::abs(ibfe.volume() / V0 - 1.0));
  }
  const double final_deviation = shape_deviation(ibfe.displacement());
  if (is_root())
    if (is_root())
      std::printf("walled box: shape deviation %.4g -> %.4g cm, max |V/V0 - 1| = %.3g\n", initial,
                  final_deviation, worst_volume);
  EXPECT_LT(worst_volume, 0.01);
  EXPECT_LT(final_deviation, 0.25 * initial);
  // Moved half out through the x = 1 wall: the coupling refuses with a RunError naming the direction.
  std::vector<double> out(solid.num_dofs(), 0.0);
  for (std::size_t n = 0; n < mesh.num_nodes(); ++n) out[3 * n] = 0.5;
  try {
    ibfe.set_displacement(out);
    ADD_FAILURE() << "no error";
  } catch (const RunError& e) {
    EXPECT_NE(std::string(e.what()).find("left the grid: direction x"), std::string::npos) << e.what();
  }
}
