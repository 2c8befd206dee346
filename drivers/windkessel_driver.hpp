#pragma once
// The three-element Windkessel (windkessel/windkessel.hpp) as a side's driver: the side gets
// P = P_Wk + R_c Q for the flow Q last given; each step's flow, linear over the step, advances P_Wk
// exactly (the exponential integrator). Its state, saved by name: time, P_Wk, Q. Its reservoir pressure
// is the report's P_Wk column on the downstream side (the name reports, scripts and the regression
// references read); upstream it is the column P_Wk_upstream.
#include "drivers/boundary_driver.hpp"
#include "windkessel/windkessel.hpp"

namespace ibvalve::drivers {

class WindkesselDriver : public BoundaryDriver {
 public:
  WindkesselDriver(Side side, const windkessel::WindkesselParameters& parameters);

  double pressure(double) const override { return windkessel_.outlet_pressure(); }
  void advance(double t, double dt, double flow) override;
  double reservoir_pressure(double) const override { return windkessel_.reservoir_pressure(); }
  std::vector<Column> columns() const override;
  std::vector<double> row(double t) const override;
  void save(io::Hdf5File& h5, const std::string& group) const override;
  void restore(const io::Hdf5File& h5, const std::string& group) override;
  std::string describe() const override;

 private:
  windkessel::ThreeElementWindkessel windkessel_;
};

} // namespace ibvalve::drivers
