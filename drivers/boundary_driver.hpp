#pragma once
// A boundary driver: what one side of a valve case gets from the circulation around it (docs/drivers.md).
//
// A valve case has an upstream side (the flow enters: the aortic valve's left ventricle) and a
// downstream side (it leaves: the aorta). Each side's pressure comes from a driver, which is told after
// every step the flow that went through its side, so the side's next pressure can answer it. The
// coupling is explicit and lagged by one step: the step from t to t + dt sees pressure(t), computed
// from the flows given up to t; after it, advance(t, dt, Q(t + dt)) moves the driver on.
//
// A driver's state goes into a checkpoint by name (one dataset per number under the driver's group),
// and its time-series columns carry the side's name (upstream, downstream), so that a driver serves
// any valve position. CGS inside; the columns are in mmHg, mL and mL/s.
#include <optional>
#include <string>
#include <vector>

#include "io/hdf5.hpp"

namespace ibvalve::drivers {

enum class Side { upstream, downstream };

/// "upstream" or "downstream".
std::string side_name(Side side);

/// A time-series column: its name and unit.
struct Column {
  std::string name;
  std::string unit;
};

class BoundaryDriver {
 public:
  virtual ~BoundaryDriver() = default;

  Side side() const { return side_; }
  /// The side's pressure for the step that starts at t (dyn/cm^2): the driver's answer to the flows
  /// given so far. The run's start-up ramp multiplies it; the driver does not know of it.
  virtual double pressure(double t) const = 0;
  /// After the step [t, t + dt]: the flow through the side at its end (cm^3/s, positive in the valve's
  /// forward direction, from upstream to downstream).
  virtual void advance(double t, double dt, double flow) = 0;
  /// The pressure of what lies behind the side at time t (dyn/cm^2): the Windkessel's reservoir, the
  /// loop's chamber or arteries, the table's value. The report's P_Wk column is the downstream driver's.
  virtual double reservoir_pressure(double t) const = 0;
  /// The beat the driver imposes on the run (the table's period, the loop's heartbeat), s; none for a
  /// driver without one (the Windkessel).
  virtual std::optional<double> period() const { return std::nullopt; }
  /// The driver's time-series columns beyond the report's own, named with the side.
  virtual std::vector<Column> columns() const = 0;
  /// Their values at time t, in the columns' units.
  virtual std::vector<double> row(double t) const = 0;
  /// The state by name: one dataset `<group>/<name>` per number.
  virtual void save(io::Hdf5File& h5, const std::string& group) const = 0;
  /// Reads back what save wrote; InputError naming the file and the dataset when one is missing.
  virtual void restore(const io::Hdf5File& h5, const std::string& group) = 0;
  /// A few words for the log: "LV pressure table (0.8 s)", "three-element Windkessel ...".
  virtual std::string describe() const = 0;

 protected:
  explicit BoundaryDriver(Side side) : side_(side) {}

 private:
  Side side_;
};

/// Writes `value` as the one-number dataset `<group>/<name>` (rank 0's value).
void save_number(io::Hdf5File& h5, const std::string& group, const std::string& name, double value);
/// Reads the one-number dataset `<group>/<name>`; InputError naming the file and the dataset when it is
/// missing or not one number (a checkpoint of another driver, or of the layout before the drivers).
double read_number(const io::Hdf5File& h5, const std::string& group, const std::string& name);

} // namespace ibvalve::drivers
