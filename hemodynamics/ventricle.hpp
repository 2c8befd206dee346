#pragma once
// The ventricle's figures of one cycle, for runs inside the closed-loop circulation (docs/hemodynamics.md,
// "The ventricle and the loop"), read from timeseries.csv: V_LV (mL) and the ventricle's pressure
// (p_LV, the loop's elastance chamber beside a 3-D valve, else P_LV, the lumped run's ventricle), over
// the cycle [t0, t1]:
//
//   EDV = max V_LV,  ESV = min V_LV,  SV = EDV - ESV,  EF = SV / EDV,
//   SW = -closed integral of p dV  (the pressure-volume loop's area, the ventricle's external work over
//        the beat; trapezoidal in the samples, mmHg mL -> mJ),
//   the valve's share E_L / SW (E_L the report's energy loss across the valve),
//
// and the periodicity of every compartment of the loop: for each chamber volume, pressure and flow
// column (V_*, p_*, Q_* beyond the report's own), |y(t1) - y(t0)| / (max y - min y over the cycle), 0
// for a periodic state; the largest of them is its own metric, naming its compartment.
#include <filesystem>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "hemodynamics/metrics.hpp"

namespace ibvalve::hemodynamics {

/// metrics.json entries (value, unit, symbol, description[, note]) by key: end_diastolic_volume,
/// end_systolic_volume, stroke_volume, ejection_fraction, stroke_work, valve_share_of_stroke_work,
/// loop_periodicity and periodicity_<column> for each compartment. Empty when the series has no V_LV
/// column (a run without the loop). `energy_loss_mJ` is E_L of the same cycle, when known.
/// std::invalid_argument when [t0, t1] holds fewer than two samples.
nlohmann::ordered_json ventricle_metrics(const std::filesystem::path& series_file, double t0, double t1,
                                         std::optional<double> energy_loss_mJ);

/// True for the keys ventricle_metrics writes (the report's group "ventricle and loop").
bool is_ventricle_metric(const std::string& key);

/// Adds ventricle_metrics of `metrics`' cycle (its E_L) to a report document's "metrics", each with its
/// group; nothing for a run without the loop.
void add_ventricle_metrics(nlohmann::ordered_json& doc, const std::filesystem::path& series_file,
                           const ValveMetrics& metrics);

} // namespace ibvalve::hemodynamics
