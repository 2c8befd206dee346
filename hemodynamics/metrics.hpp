#pragma once
// Hemodynamic metrics of one cardiac cycle of a valve run (docs/reference.md, "Hemodynamic metrics"),
// with the cycle's phases detected from the flow (and the orifice area when there is one).
//
// Phase rules (every threshold is a setting; docs/hemodynamics.md explains them with figures):
//  * Cycle: [t0 + (k-1) T, t0 + k T], T = `period`, t0 the first sample, k = `cycle` counted from 1
//    (-1: the last whole cycle in the series). Columns are interpolated linearly at the two ends.
//  * Forward flow [t_ff, t_es]: the lobe of Q > forward_threshold that holds the cycle's largest
//    flow; its ends are the threshold crossings next to the peak, found by linear interpolation.
//  * Ejection [t_bs, t_es], the valve open and the flow forward: t_bs is the latest of three instants
//    before the peak flow, each the start of its condition's last rise: forward flow (t_ff), the
//    pressure across the leaflets turned forward (P_nlv - P_nao rises through 0) and, with a varying
//    orifice area, the orifice opening (the opening phase's start below). Closed leaflets that bulge
//    as the ventricle's pressure rises push fluid through the flow plane before the valve opens; that
//    displacement flow is forward flow but not ejection. The TPG, Q_rms and EOA are means over
//    [t_bs, t_es]; the report gives them also on the windows the other two instants would open.
//  * Closure t_c, rule "flow" (the default): after t_es, find the peak regurgitant flow Q_min (most
//    negative Q before the end of the cycle) and the leakage flow Q_end (Q at the end of the cycle,
//    late diastole); t_c is the first time after the peak that Q has recovered to
//    Q_end + closure_flow_fraction (Q_min - Q_end), i.e. (1 - fraction) of the way back from the
//    backflow peak to the leakage flow (linear interpolation). If it never does, t_c is the time of
//    the largest Q after the peak. Rule "area": t_c is the end of the closing phase below
//    (normalised area falls to closed_area_fraction). Rule "auto": "area" when an orifice-area column
//    varies, else "flow".
//  * Closing regurgitation [t_es, t_c]; leakage [t_c, t1], from closure to the cycle's end (the study's
//    definition, docs/reference.md); the flow before forward flow, [t0, t_ff], is in neither.
//  * Orifice area a(t) = (A - A_min) / (A_max - A_min), A_max the cycle's largest area and A_min the
//    smallest on the same side of it (before it for the opening, after it for the closing): opening
//    from the last upward crossing of closed_area_fraction before a first reaches open_area_fraction,
//    fully open from then to the last time a >= open_area_fraction, closing from then to the next
//    downward crossing of closed_area_fraction.
// Metrics (integrals: trapezoidal rule on the samples, ends of phases interpolated linearly):
//  V_F = int_{t_ff}^{t_es} Q;  V_R = -int_{t_es}^{t_c} Q;  V_L = -int_{t_c}^{t1} Q;
//  RF = (V_R + V_L) / V_F * 100;  TPG = mean over [t_bs, t_es] of P_nlv - P_nao;
//  Q_rms = sqrt(mean over [t_bs, t_es] of Q^2);  EOA = Q_rms / (51.6 sqrt(TPG / rho));
//  E_L = k * int_{t0}^{t1} (P_LV - P_Ao) Q dt with k = 1 mmHg mL in mJ (0.133322): the study writes
//  dp = P_Ao - P_LV; with that sign the loss would come out negative, so ibvalve uses
//  dp = P_LV - P_Ao and reports E_L > 0 for energy dissipated across the valve.
//  Peak forward / regurgitant flow: max Q over the cycle and -min Q after ejection (refined by a
//  parabola through the three samples around the extreme), each noted with its own instant.
//  EROA_d = max |Q| / sqrt(2 min(P_nao - P_nlv) / rho) over the cycle's last quarter: the closed
//  criterion (docs/hemodynamics.md, "Closed"). P_Wk at the cycle's ends and the outlet volume say how
//  periodic the cycle is.
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "hemodynamics/timeseries.hpp"

namespace ibvalve::hemodynamics {

enum class ClosureRule { automatic, flow, area };
ClosureRule closure_rule_from_name(const std::string& name); // "auto", "flow", "area"
std::string closure_rule_name(ClosureRule rule);

struct MetricSettings {
  double period = 0.8;            // s, the cardiac cycle
  int cycle = -1;                 // which cycle, counted from 1 (1 = the first); -1 = the last whole cycle
  double forward_threshold = 0.0; // mL/s: forward ejection is Q above this
  ClosureRule closure_rule = ClosureRule::flow;
  double closure_flow_fraction =
      0.1; // rule "flow": closed once Q is this fraction of the way from Q_end to Q_min
  double open_area_fraction = 0.9;    // normalised area counted as fully open
  double closed_area_fraction = 0.05; // normalised area counted as closed
  double density = 1.0;               // g/mL, for EOA: the fluid's (fluid.density of the run)
};

/// Instants of the analysed cycle, s (NaN when a phase was not found).
struct Phases {
  static constexpr double not_found = std::numeric_limits<double>::quiet_NaN();
  double cycle_start = not_found, cycle_end = not_found;
  double forward_flow_start = not_found; // t_ff: the forward-flow lobe's start
  double pressure_crossover = not_found; // P_nlv - P_nao's last rise through 0 before the peak flow
  double ejection_start = not_found, ejection_end = not_found; // t_bs, t_es
  std::string ejection_start_condition; // which condition set t_bs: "forward flow", "pressure crossover"
                                        // or "orifice opening"
  double closure = not_found;           // t_c
  double peak_forward_time = not_found, peak_regurgitant_time = not_found;
  std::string closure_rule; // the rule applied ("flow" or "area")
  // From the orifice area (NaN without one).
  double opening_start = not_found, fully_open_start = not_found, fully_open_end = not_found,
         closing_end = not_found;
};

/// The means over ejection on the window one condition alone would open, [start, t_es]: how far the
/// TPG, Q_rms and EOA depend on the rule for t_bs.
struct EjectionWindow {
  std::string condition; // "forward flow", "pressure crossover" or "orifice opening"
  double start = 0.0;    // s
  double transvalvular_pressure_gradient = 0.0, rms_forward_flow = 0.0; // mmHg, mL/s
  std::optional<double> effective_orifice_area;                         // cm^2, missing if TPG <= 0
};

/// One reported quantity. `value` is empty when it cannot be computed for this run (with `note`).
struct Metric {
  std::string key;    // metrics.json key, e.g. "forward_volume"
  std::string symbol; // as in the study, e.g. "V_F"
  std::string unit;   // report unit, e.g. "mL"
  std::string description;
  std::optional<double> value;
  std::string note;
};

struct ValveMetrics {
  int cycle = 0;  // the analysed cycle, counted from 1
  int cycles = 0; // the whole cycles the series holds
  Phases phases;
  std::vector<Metric> metrics;
  std::vector<std::string> notes;               // how the phases were found, what is missing and why
  std::vector<EjectionWindow> ejection_windows; // one per condition found, the chosen one among them
  const Metric* find(const std::string& key) const;
  /// The value of a metric, or NaN when missing or unknown.
  double value(const std::string& key) const;
};

/// Phases and metrics of one cycle. std::invalid_argument when the series does not hold the cycle
/// asked for (too short for one period, cycle 0 or beyond the series' whole cycles).
ValveMetrics compute_metrics(const ValveSeries& series, const MetricSettings& settings);

/// The whole cycles of `period` the series holds (std::invalid_argument for a period that is not
/// positive).
int whole_cycles(const ValveSeries& series, double period);

/// 1 mmHg mL in mJ: the study's 0.1333.
double mmHg_mL_in_mJ();

} // namespace ibvalve::hemodynamics
