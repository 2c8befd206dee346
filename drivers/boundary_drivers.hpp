#pragma once
// A valve case's two drivers, upstream and downstream, and the model they may share (the closed loop
// drives both sides): the one object the case's run talks to (docs/drivers.md).
#include <memory>
#include <string>
#include <vector>

#include "drivers/boundary_driver.hpp"
#include "drivers/closed_loop_driver.hpp"

namespace ibvalve::drivers {

class BoundaryDrivers {
 public:
  BoundaryDrivers(std::unique_ptr<BoundaryDriver> upstream, std::unique_ptr<BoundaryDriver> downstream,
                  std::shared_ptr<ClosedLoopCoupling> loop = nullptr);

  const BoundaryDriver& upstream() const { return *upstream_; }
  const BoundaryDriver& downstream() const { return *downstream_; }
  /// The closed loop both sides share, or null.
  const ClosedLoopCoupling* loop() const { return loop_.get(); }
  /// The run's beat: the upstream driver's, else the downstream's; none when neither has one.
  std::optional<double> period() const;

  /// After the step [t, t + dt]: the flows through the two sides at its end (cm^3/s, forward positive).
  void advance(double t, double dt, double upstream_flow, double downstream_flow);

  /// The columns the drivers add to the time series: upstream's, downstream's, then the shared loop's.
  std::vector<Column> columns() const;
  std::vector<double> row(double t) const;
  /// Checkpoint: drivers/upstream/..., drivers/downstream/..., drivers/loop/..., each number by name.
  void save(io::Hdf5File& h5) const;
  /// Reads them back; a checkpoint written before the drivers (aortic_valve/outlet, numbers by position)
  /// is refused with an InputError saying so.
  void restore(const io::Hdf5File& h5);
  /// One line per driver, for the log.
  std::vector<std::string> describe() const;

 private:
  std::unique_ptr<BoundaryDriver> upstream_, downstream_;
  std::shared_ptr<ClosedLoopCoupling> loop_;
};

} // namespace ibvalve::drivers
