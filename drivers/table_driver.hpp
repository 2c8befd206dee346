#pragma once
// The prescribed pressure: a periodic table (windkessel/waveform.hpp) whatever the flow. Stateless: its
// checkpoint holds nothing, its columns are none (the table is in the case's file; the probes measure
// what the fluid gets).
#include "drivers/boundary_driver.hpp"
#include "windkessel/waveform.hpp"

namespace ibvalve::drivers {

class TableDriver : public BoundaryDriver {
 public:
  TableDriver(Side side, windkessel::PeriodicWaveform table, std::string what);

  double pressure(double t) const override { return table_(t); }
  void advance(double, double, double) override {}
  double reservoir_pressure(double t) const override { return table_(t); }
  std::optional<double> period() const override { return table_.period(); }
  std::vector<Column> columns() const override { return {}; }
  std::vector<double> row(double) const override { return {}; }
  void save(io::Hdf5File&, const std::string&) const override {}
  void restore(const io::Hdf5File&, const std::string&) override {}
  std::string describe() const override;

 private:
  windkessel::PeriodicWaveform table_;
  std::string what_; // "LV pressure table", for the log
};

} // namespace ibvalve::drivers
