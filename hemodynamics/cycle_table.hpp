#pragma once
// The cycle-to-cycle table of a report: how far the reported cycle repeats the ones before it, the
// figures that settle last as a run approaches its periodic state (docs/hemodynamics.md, "One report
// per cycle").
#include <string>

#include <nlohmann/json.hpp>

#include "hemodynamics/metrics.hpp"
#include "hemodynamics/timeseries.hpp"

namespace ibvalve::hemodynamics {

/// |P_Wk at the cycle's end - at its start| beyond which the cycle is flagged as not periodic, mmHg:
/// the resolution at which a clinical pressure is read, about 1.5 % of the diastolic aortic pressure of
/// the default run (65-68 mmHg).
inline constexpr double periodic_pressure_tolerance = 1.0;

/// metrics.json's "cycles": one row per cycle 1 .. `last` of the series (cycles of settings.period,
/// counted from 1): {"cycle", "forward_volume" (mL), "transvalvular_pressure_gradient" (mmHg),
/// "windkessel_pressure_start", "windkessel_pressure_end" (mmHg)}, null where the cycle has no value.
nlohmann::ordered_json cycle_table(const ValveSeries& series, const MetricSettings& settings, int last);

/// One sentence on how periodic the table's last cycle is: its V_F and TPG against the cycle before
/// (relative change) and its Windkessel pressure's change over the cycle against
/// periodic_pressure_tolerance. Empty for a table of fewer than two cycles.
std::string periodicity_summary(const nlohmann::ordered_json& cycles);

} // namespace ibvalve::hemodynamics
