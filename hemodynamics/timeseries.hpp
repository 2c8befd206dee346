#pragma once
// A run's timeseries.csv: the columns every valve run writes and the reader the metrics use.
//
// The file is a user-facing artefact, so its values are in report units: t in s, flows in mL/s,
// pressures in mmHg, areas in cm^2 (the metric formulas of the study, EOA = Q_rms / (51.6 sqrt(TPG/rho))
// and E_L = 0.1333 * integral of dp Q, are written in these units). Runs write the columns named
// below; a run may add more columns, which are ignored here.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace ibvalve::hemodynamics {

namespace column {
inline constexpr const char* time = "t";                     // s
inline constexpr const char* valve_flow = "Q_valve";         // mL/s through the valve, positive forward
inline constexpr const char* outlet_flow = "Q_outlet";       // mL/s out through the outlet
inline constexpr const char* lv_pressure = "P_LV";           // mmHg, centre of the inlet
inline constexpr const char* aortic_pressure = "P_Ao";       // mmHg, centre of the outlet
inline constexpr const char* windkessel_pressure = "P_Wk";   // mmHg, Windkessel reservoir
inline constexpr const char* near_lv_pressure = "P_nlv";     // mmHg, near the leaflets, LV side
inline constexpr const char* near_aortic_pressure = "P_nao"; // mmHg, near the leaflets, aortic side
inline constexpr const char* orifice_area = "orifice_area";  // cm^2 (geometric, or effective for lumped runs)
// The leaflets' state, written by 3-D runs (optional; the metrics read them at the orifice phases'
// instants, docs/hemodynamics.md, "Leaflet state").
inline constexpr const char* displacement_mean = "d_mean";      // cm, mean |x - X| over the leaflet nodes
inline constexpr const char* displacement_max = "d_max";        // cm, largest |x - X| over them
inline constexpr const char* peak_velocity = "u_max";           // cm/s, largest fluid speed in the jet
inline constexpr const char* belly_fiber_strain = "E_ff_belly"; // f0 . (E f0), mean over the belly spheres
inline constexpr const char* top_fiber_strain = "E_ff_top";     // the same over the top-centre spheres
inline constexpr const char* belly_fiber_stress = "S_ff_belly"; // kPa, f . (sigma f), belly spheres
inline constexpr const char* top_fiber_stress = "S_ff_top";     // kPa, top-centre spheres
} // namespace column

/// The leaflet-state columns, in the order runs write them after the standard ones, and their units.
std::vector<std::string> leaflet_state_columns();
std::vector<std::string> leaflet_state_units();

/// The standard columns in the order runs write them.
std::vector<std::string> standard_columns();
/// Their units, in the same order (timeseries.csv's units line, io::CsvWriter).
std::vector<std::string> standard_units();

/// Samples of one run (report units). Optional columns are empty when the file lacks them.
struct ValveSeries {
  std::vector<double> t;
  std::vector<double> valve_flow;
  std::vector<double> outlet_flow; // optional
  std::vector<double> lv_pressure;
  std::vector<double> aortic_pressure;
  std::vector<double> windkessel_pressure; // optional
  std::vector<double> near_lv_pressure;
  std::vector<double> near_aortic_pressure;
  std::vector<double> orifice_area; // optional
  /// The leaflet-state columns the file has (leaflet_state_columns() names), each optional.
  std::map<std::string, std::vector<double>> leaflet_state;
  std::filesystem::path source;

  std::size_t size() const { return t.size(); }
  bool has_orifice_area() const { return !orifice_area.empty(); }
  /// Every non-empty column, so that operations apply to all of them alike.
  std::vector<std::vector<double>*> columns();
  std::vector<const std::vector<double>*> columns() const;
};

/// Reads timeseries.csv. Required: t, Q_valve, P_LV, P_Ao, P_nlv, P_nao; optional: Q_outlet, P_Wk,
/// orifice_area and the leaflet-state columns. A missing file or column, a malformed line, a non-finite value
/// or times that do not increase strictly are InputErrors naming the file (and line).
ValveSeries read_valve_series(const std::filesystem::path& file);

/// The samples in [start, end], with every column interpolated linearly at the two ends when they
/// fall between samples. std::invalid_argument when [start, end] is not inside the series.
ValveSeries time_window(const ValveSeries& series, double start, double end);

/// The linear interpolant of samples (t, y) at time x (t increasing, x within [t.front(), t.back()]).
double interpolate(const std::vector<double>& t, const std::vector<double>& y, double x);

/// The integral over [a, b] of the piecewise-linear interpolant of (t, y): the trapezoidal rule, with
/// partial intervals at the ends integrated exactly. Second-order accurate in the sampling interval.
double integrate(const std::vector<double>& t, const std::vector<double>& y, double a, double b);

} // namespace ibvalve::hemodynamics
