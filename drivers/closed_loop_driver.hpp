#pragma once
// The closed-loop circulation (circulation/closed_loop.hpp, Regazzoni et al. 2022) around a 3-D valve in
// the aortic position (docs/drivers.md, "The closed loop"): the loop's left ventricle drives the upstream
// side, p = E_LV(t) (V_LV - V_0), and loses the flow through that side; the loop's systemic arteries
// drive the downstream side, p_AR^SYS, and take in the flow through it. The loop's own aortic valve is
// not used: the 3-D valve is it.
//
// One ClosedLoopCoupling holds the loop's state; its two sides are two BoundaryDriver views of it. The
// loop steps once both sides have given their step's flow (classical RK4 over the step, the two 3-D
// flows linear in time from the last given to the new: circulation::ExternalAorticFlow), so the
// coupling is explicit, lagged by one step as the Windkessel's; docs/drivers.md measures its margin.
//
// Before the run's t = 0 the loop runs `start_beats` beats on its own (its diode aortic valve), from the
// published initial state, so that the 3-D valve joins a loop near its periodic state.
#include <array>
#include <memory>
#include <optional>

#include "circulation/closed_loop.hpp"
#include "drivers/boundary_driver.hpp"

namespace ibvalve::drivers {

class ClosedLoopCoupling {
 public:
  /// The loop (its aortic valve must be the diode: the one used before t = 0) settled by `start_beats`
  /// beats of `steps_per_beat` RK4 steps each.
  ClosedLoopCoupling(const circulation::CirculationParameters& parameters, int start_beats,
                     long steps_per_beat);

  const circulation::ClosedLoop& loop() const { return loop_; }
  double period() const { return loop_.period(); }
  /// p_LV = E_LV(t) (V_LV - V_0,LV), dyn/cm^2.
  double ventricle_pressure(double t) const;
  /// p_AR^SYS, dyn/cm^2.
  double arterial_pressure() const { return y_[circulation::p_AR_SYS]; }
  /// The flow a side gave for the step [t, t + dt]; once both have, the loop steps.
  void give_flow(Side side, double t, double dt, double flow);
  /// The flow last given through a side (cm^3/s).
  double flow(Side side) const { return flow_[index(side)]; }

  /// The loop's columns by compartment: chamber volumes (mL), pressures (mmHg), flows (mL/s), and the
  /// blood volume V_blood (mL), which the 3-D model changes by what its tube stores or leaks.
  std::vector<Column> columns() const;
  std::vector<double> row(double t) const;
  /// The loop's state by name under `group`, each entry of ClosedLoop::state_names(), the two sides'
  /// last flows and the time.
  void save(io::Hdf5File& h5, const std::string& group) const;
  void restore(const io::Hdf5File& h5, const std::string& group);
  std::string describe() const;

 private:
  static std::size_t index(Side side) { return side == Side::upstream ? 0 : 1; }

  circulation::ClosedLoop loop_;
  circulation::ClosedLoop::State y_;
  double time_ = 0.0;
  int start_beats_ = 0;
  std::array<double, 2> flow_{0.0, 0.0};           // the flows the last step ended with
  std::array<std::optional<double>, 2> pending_{}; // this step's, until both sides have given theirs
};

/// One side of the loop: upstream the left ventricle, downstream the systemic arteries. Columns
/// P_<side> (mmHg, the pressure the side gets) and Q_<side> (mL/s, the flow given through it).
class ClosedLoopSide : public BoundaryDriver {
 public:
  ClosedLoopSide(Side side, std::shared_ptr<ClosedLoopCoupling> coupling);

  double pressure(double t) const override;
  void advance(double t, double dt, double flow) override { coupling_->give_flow(side(), t, dt, flow); }
  double reservoir_pressure(double t) const override { return pressure(t); }
  std::optional<double> period() const override { return coupling_->period(); }
  std::vector<Column> columns() const override;
  std::vector<double> row(double t) const override;
  // The loop's state is the coupling's (BoundaryDrivers saves it once); a side has none of its own.
  void save(io::Hdf5File&, const std::string&) const override {}
  void restore(const io::Hdf5File&, const std::string&) override {}
  std::string describe() const override;

 private:
  std::shared_ptr<ClosedLoopCoupling> coupling_;
};

} // namespace ibvalve::drivers
