// The boundary drivers (drivers/): the Windkessel driver is the Windkessel; the closed loop keeps its
// blood but for what the outside model stores; a checkpoint restores every driver by name and refuses
// the layout before the drivers; the explicit coupling's margin measured on a lumped stand-in for the
// 3-D valve against its predicted limit (docs/drivers.md, "The closed loop's coupling").
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <numbers>

#include <gtest/gtest.h>
#include <mpi.h>

#include "base/errors.hpp"
#include "base/units.hpp"
#include "circulation/closed_loop.hpp"
#include "drivers/boundary_drivers.hpp"
#include "drivers/closed_loop_driver.hpp"
#include "drivers/table_driver.hpp"
#include "drivers/windkessel_driver.hpp"
#include "windkessel/windkessel.hpp"

namespace ibvalve::drivers {
namespace {

constexpr double mmHg = units::mmHg, mL = units::mL;

std::filesystem::path scratch(const std::string& name)
{
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return std::filesystem::temp_directory_path() /
         ("ibvalve_test_drivers_" + name + std::to_string(rank) + ".h5");
}

windkessel::WindkesselParameters stergiopulos()
{
  return *windkessel::preset("stergiopulos-typeA");
}

/// A flow that ejects for 0.3 s of a 0.8 s beat, mL/s.
double ejection(double t)
{
  const double s = std::fmod(t, 0.8);
  return s < 0.3 ? 400.0 * std::sin(std::numbers::pi * s / 0.3) * mL : 0.0;
}

TEST(WindkesselDriver, GivesTheWindkesselsPressureBitForBit)
{
  WindkesselDriver driver(Side::downstream, stergiopulos());
  windkessel::ThreeElementWindkessel reference(stergiopulos());
  double expected = reference.outlet_pressure();
  const double dt = 4e-5;
  for (int n = 0; n < 20000; ++n) {
    const double t = n * dt;
    ASSERT_EQ(driver.pressure(t), expected) << "step " << n;
    expected = reference.advance(dt, ejection(t + dt));
    driver.advance(t, dt, ejection(t + dt));
  }
  EXPECT_EQ(driver.reservoir_pressure(0.0), reference.reservoir_pressure());
  EXPECT_TRUE(driver.columns().empty()); // downstream its reservoir is the report's own P_Wk
  EXPECT_EQ(WindkesselDriver(Side::upstream, stergiopulos()).columns().at(0).name, "P_Wk_upstream");
}

TEST(ClosedLoopCoupling, KeepsItsBloodButWhatTheOutsideModelStores)
{
  const auto loop = std::make_shared<ClosedLoopCoupling>(circulation::regazzoni2022(), 1, 2000);
  ClosedLoopSide upstream(Side::upstream, loop), downstream(Side::downstream, loop);
  auto blood = [&] { return loop->row(0.0).back() * mL; }; // V_blood, the last column
  const double start = blood();
  const double dt = loop->period() / 4000.0;
  // The same flow leaves the ventricle and enters the arteries: the blood is kept to round-off.
  for (int n = 0; n < 4000; ++n) {
    upstream.advance(n * dt, dt, ejection((n + 1) * dt));
    downstream.advance(n * dt, dt, ejection((n + 1) * dt));
  }
  EXPECT_LT(std::abs(blood() - start) / start, 1e-13);
  // 2 mL/s more leaves the ventricle than reaches the arteries (a tube that stores it): the loop loses
  // exactly that, the flows being linear over each step.
  const double lost = 2.0 * mL;
  for (int n = 4000; n < 8000; ++n) {
    upstream.advance(n * dt, dt, ejection((n + 1) * dt) + lost);
    downstream.advance(n * dt, dt, ejection((n + 1) * dt));
  }
  const double expected = start - lost * (4000 - 0.5) * dt; // the first step ramps from 0 to 2 mL/s
  EXPECT_NEAR(blood(), expected, 1e-11 * start);
}

TEST(BoundaryDrivers, RestoreEveryDriverByName)
{
  auto make = [] {
    auto loop = std::make_shared<ClosedLoopCoupling>(circulation::regazzoni2022(), 0, 1000);
    return BoundaryDrivers(std::make_unique<ClosedLoopSide>(Side::upstream, loop),
                           std::make_unique<ClosedLoopSide>(Side::downstream, loop), loop);
  };
  BoundaryDrivers first = make(), second = make();
  const double dt = 1e-4;
  for (int n = 0; n < 3000; ++n)
    first.advance(n * dt, dt, ejection((n + 1) * dt), 0.9 * ejection((n + 1) * dt));
  const std::filesystem::path file = scratch("names");
  {
    io::Hdf5File h5(MPI_COMM_SELF, file, io::Hdf5File::Mode::create);
    first.save(h5);
    h5.close();
  }
  {
    io::Hdf5File h5(MPI_COMM_SELF, file, io::Hdf5File::Mode::read);
    second.restore(h5);
  }
  const double t = 3000 * dt;
  EXPECT_EQ(first.row(t), second.row(t));
  EXPECT_EQ(first.upstream().pressure(t), second.upstream().pressure(t));
  for (int n = 3000; n < 3100; ++n) {
    first.advance(n * dt, dt, ejection((n + 1) * dt), ejection((n + 1) * dt));
    second.advance(n * dt, dt, ejection((n + 1) * dt), ejection((n + 1) * dt));
  }
  EXPECT_EQ(first.row(0.31), second.row(0.31));
  // A Windkessel case cannot read the loop's checkpoint: the missing name is said.
  BoundaryDrivers table_case(
      std::make_unique<TableDriver>(
          Side::upstream,
          windkessel::PeriodicWaveform({0.0, 0.8}, {1.0, 1.0}, windkessel::Interpolation::linear), "table"),
      std::make_unique<WindkesselDriver>(Side::downstream, stergiopulos()));
  {
    io::Hdf5File h5(MPI_COMM_SELF, file, io::Hdf5File::Mode::read);
    try {
      table_case.restore(h5);
      FAIL() << "restored a Windkessel from the loop's checkpoint";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("drivers/downstream/time is missing"), std::string::npos)
          << e.what();
    }
  }
  std::filesystem::remove(file);
}

TEST(BoundaryDrivers, RefuseTheCheckpointLayoutBeforeTheDrivers)
{
  const std::filesystem::path file = scratch("old");
  {
    io::Hdf5File h5(MPI_COMM_SELF, file, io::Hdf5File::Mode::create);
    const std::vector<double> old{0.1, 85.0 * mmHg, 0.0, 85.0 * mmHg, 0.0, 1.0, 0.0};
    h5.write_root("aortic_valve/outlet", old, std::vector<hsize_t>{old.size()});
    h5.close();
  }
  BoundaryDrivers drivers(std::make_unique<WindkesselDriver>(Side::upstream, stergiopulos()),
                          std::make_unique<WindkesselDriver>(Side::downstream, stergiopulos()));
  io::Hdf5File h5(MPI_COMM_SELF, file, io::Hdf5File::Mode::read);
  try {
    drivers.restore(h5);
    FAIL() << "read a checkpoint of the older layout";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("layout before the boundary drivers"), std::string::npos)
        << e.what();
  }
  std::filesystem::remove(file);
}

/// The largest |p_LV| over three beats of the loop around a stand-in for the 3-D valve, driven through the
/// drivers as the 3-D run drives them: after each step of dt the stand-in's flow, from the pressures the
/// sides had at the step's start, Q = (p_up - p_down) / R (an open valve of resistance R), is given to
/// both sides. Infinity when the pressures stop being finite.
double peak_ventricle_pressure(double dt, double resistance)
{
  const auto loop = std::make_shared<ClosedLoopCoupling>(circulation::regazzoni2022(), 20, 2000);
  ClosedLoopSide upstream(Side::upstream, loop), downstream(Side::downstream, loop);
  double peak = 0.0;
  const long steps = std::lround(3.0 * loop->period() / dt);
  for (long n = 0; n < steps; ++n) {
    const double t = static_cast<double>(n) * dt;
    const double q = (upstream.pressure(t) - downstream.pressure(t)) / resistance;
    upstream.advance(t, dt, q);
    downstream.advance(t, dt, q);
    const double p = std::abs(upstream.pressure(t + dt));
    if (!std::isfinite(p)) return INFINITY;
    peak = std::max(peak, p);
  }
  return peak;
}

// The explicit coupling's margin (docs/drivers.md): with the flow lagged by one step and linear over the
// next, a valve of resistance R between the ventricle (elastance E) and the arteries (compliance C)
// gives p^{n+1} = p^n - c (p^n + p^{n-1}), c = dt (E + 1/C) / (2R), whose roots stay in the unit circle
// while c < 1: dt < 2R / (E_max + 1/C), a bound (E reaches E_max for an instant only). Measured: stable
// and equal to a hundredfold finer step at the bound; the pressures explode at 1.5 times it (the
// measured limit lies between 1.30 and 1.35 times it).
TEST(ClosedLoopCoupling, ExplicitCouplingIsStableBelowItsPredictedStep)
{
  const circulation::CirculationParameters p = circulation::regazzoni2022();
  const double resistance = p.aortic.open_resistance; // the loop's own open valve, 0.0075 mmHg s/mL
  const double bound = 2.0 * resistance /
                       (p.left_ventricle.active_elastance + p.left_ventricle.passive_elastance +
                        1.0 / p.systemic_arterial.compliance);
  EXPECT_NEAR(bound, 4.095e-3, 1e-6);
  const double fine = peak_ventricle_pressure(0.01 * bound, resistance);
  EXPECT_GT(fine, 100.0 * mmHg);
  EXPECT_LT(fine, 200.0 * mmHg);
  EXPECT_NEAR(peak_ventricle_pressure(bound, resistance), fine, 1e-3 * fine);
  EXPECT_GT(peak_ventricle_pressure(1.5 * bound, resistance), 1e6 * fine);
}

} // namespace
} // namespace ibvalve::drivers
