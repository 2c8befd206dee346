// Where the aortic-valve model measures its peak velocity (app/jet_region.hpp): between the pressure
// probes in the tube's lumen, its ends kept off the box's pressure sides, so that a field whose largest
// speed sits in the outlet's last cell layer (as the default run's does through systole) gives the
// jet's speed, not the outlet's. On 1 and 2 ranks.
#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>
#include <petscsys.h>

#include "app/jet_region.hpp"
#include "fluid/navier_stokes.hpp"

using namespace ibvalve;

namespace {

// The default case's box, at a coarser grid: the tube's axis at x = y = 0, the outlet side at the top.
fluid::BoxGeometry valve_box()
{
  fluid::BoxGeometry box;
  box.lower = {-1.75, -1.75, -0.0625};
  box.upper = {1.75, 1.75, 5.0625};
  box.cells = {14, 14, 20};
  box.periodic = {false, false, false};
  return box;
}

TEST(JetRegion, LiesBetweenTheProbesInTheTube)
{
  const fluid::BoxGeometry box = valve_box();
  // The default probes: 1 cm below the nadir (z = 2) and above the commissures (z = 3.2).
  const app::JetRegion jet = app::jet_region(1.0, 4.2, 1.3, box);
  EXPECT_DOUBLE_EQ(jet.lower, 1.0);
  EXPECT_DOUBLE_EQ(jet.upper, 4.2);
  EXPECT_TRUE(jet.contains({0.0, 0.0, 2.5}));
  EXPECT_TRUE(jet.contains({1.29, 0.0, 4.2}));
  EXPECT_FALSE(jet.contains({1.31, 0.0, 2.5}));         // outside the lumen
  EXPECT_FALSE(jet.contains({0.0, 0.0, 4.3}));          // above the upper probe
  EXPECT_FALSE(jet.contains({0.0, 0.0, 5.0625 - 0.1})); // the outlet's last layer
  EXPECT_NE(jet.describe().find("1 <= z <= 4.2 cm"), std::string::npos) << jet.describe();
}

TEST(JetRegion, KeepsTwoCellLayersOffTheBoxSides)
{
  const fluid::BoxGeometry box = valve_box();
  const double h = box.spacing(2);
  // Probes beyond the box's ends: the region stops two cell layers inside it.
  const app::JetRegion jet = app::jet_region(-1.0, 9.0, 1.3, box);
  EXPECT_DOUBLE_EQ(jet.lower, box.lower[2] + 2.0 * h);
  EXPECT_DOUBLE_EQ(jet.upper, box.upper[2] - 2.0 * h);
  // Nothing left between them: an error, not an empty region that reads 0.
  EXPECT_THROW(app::jet_region(4.99, 5.05, 1.3, box), std::invalid_argument);
}

TEST(JetRegion, PeakVelocityIsTheJetsNotTheOutletLayers)
{
  const fluid::BoxGeometry box = valve_box();
  fluid::BoundaryConditions bc;
  // Traction sides, as the valve's box has: the outlet side's normal velocity is the flow's own.
  for (int s = 0; s < 6; ++s) bc.side(s).kind = fluid::SideKind::traction;
  fluid::FluidSettings settings;
  settings.solver = fluid::SolverKind::krylov;
  fluid::NavierStokes fluid(PETSC_COMM_WORLD, box, bc, settings);
  // A jet of 300 cm/s along the axis (r < 0.5 cm) from z = 1 to 4 cm, and 450 cm/s across the outlet's
  // last cell layer (both its faces), where the box's largest speed then sits.
  const double outlet_layer = box.upper[2] - box.spacing(2) - 1e-9;
  fluid.set_initial_condition(
      [&](const fluid::Real3& x, double) {
        const bool jet = std::hypot(x[0], x[1]) < 0.5 && x[2] >= 1.0 && x[2] <= 4.0;
        return fluid::Real3{0.0, 0.0, x[2] >= outlet_layer ? 450.0 : (jet ? 300.0 : 0.0)};
      },
      nullptr, 0.0);
  const app::JetRegion jet = app::jet_region(1.0, 4.2, 1.3, box);
  EXPECT_DOUBLE_EQ(fluid.max_velocity(), 450.0);
  EXPECT_DOUBLE_EQ(fluid.max_speed_in(jet.points()), 300.0);
  // A region holding no cell centre reads 0.
  EXPECT_DOUBLE_EQ(fluid.max_speed_in([](const fluid::Real3&) { return false; }), 0.0);
}

} // namespace
