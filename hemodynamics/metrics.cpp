#include "hemodynamics/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "base/units.hpp"

namespace ibvalve::hemodynamics {

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

/// Where the linear interpolant between samples i and i+1 takes `level`.
double crossing(const std::vector<double>& t, const std::vector<double>& y, std::size_t i, double level)
{
  const double dy = y[i + 1] - y[i];
  if (dy == 0.0) return t[i];
  const double s = std::clamp((level - y[i]) / dy, 0.0, 1.0);
  return t[i] + s * (t[i + 1] - t[i]);
}

struct Extreme {
  double time = nan, value = nan;
};

/// The extreme sample i refined by the parabola through samples i-1, i, i+1 (non-uniform spacing).
Extreme refine_extreme(const std::vector<double>& t, const std::vector<double>& y, std::size_t i)
{
  Extreme e{t[i], y[i]};
  if (i == 0 || i + 1 >= t.size()) return e;
  // Only a strict extreme sample is refined: on a plateau the samples already hold the extreme.
  const bool strict_max = y[i] > y[i - 1] && y[i] > y[i + 1], strict_min = y[i] < y[i - 1] && y[i] < y[i + 1];
  if (!strict_max && !strict_min) return e;
  const double a = t[i - 1], b = t[i], c = t[i + 1];
  const double fab = (y[i] - y[i - 1]) / (b - a), fbc = (y[i + 1] - y[i]) / (c - b);
  const double fabc = (fbc - fab) / (c - a);
  if (fabc == 0.0) return e;
  const double x = 0.5 * (a + b) - fab / (2.0 * fabc);
  if (x < a || x > c) return e;
  e.time = x;
  e.value = y[i - 1] + fab * (x - a) + fabc * (x - a) * (x - b);
  return e;
}

/// Where y last rose above `level` at or before sample i: the start of the run of samples above
/// `level` that holds i or, when y[i] <= level, of the last such run before i; t[0] when the run holds
/// the first sample; NaN when y is not above `level` anywhere up to i.
double last_rise(const std::vector<double>& t, const std::vector<double>& y, std::size_t i, double level)
{
  std::size_t j = i;
  while (j > 0 && !(y[j] > level)) --j;
  if (!(y[j] > level)) return nan;
  while (j > 0 && y[j - 1] > level) --j;
  return j == 0 ? t[0] : crossing(t, y, j - 1, level);
}

std::size_t argmax(const std::vector<double>& y, std::size_t from, std::size_t to)
{
  std::size_t best = from;
  for (std::size_t i = from; i < to; ++i)
    if (y[i] > y[best]) best = i;
  return best;
}

std::size_t argmin(const std::vector<double>& y, std::size_t from, std::size_t to)
{
  std::size_t best = from;
  for (std::size_t i = from; i < to; ++i)
    if (y[i] < y[best]) best = i;
  return best;
}

std::vector<double> combine(const std::vector<double>& a, const std::vector<double>& b, auto op)
{
  std::vector<double> out(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) out[i] = op(a[i], b[i]);
  return out;
}

std::string seconds(double t)
{
  return fmt::format("{:.4f} s", t);
}

namespace condition {
constexpr const char* forward_flow = "forward flow";
constexpr const char* pressure = "pressure crossover";
constexpr const char* orifice = "orifice opening";
} // namespace condition

/// t_bs, the ejection's start (metrics.hpp): the latest of the forward flow's start, the pressure
/// crossover and the orifice's opening that come before the forward flow's end. Sets
/// ph.pressure_crossover too; ph.forward_flow_start, ph.ejection_end and the orifice phases are set.
void set_ejection_start(const std::vector<double>& t, const std::vector<double>& gradient, std::size_t i_peak,
                        bool area_phases, Phases& ph, std::vector<std::string>& notes)
{
  ph.pressure_crossover = last_rise(t, gradient, i_peak, 0.0);
  if (std::isnan(ph.pressure_crossover))
    notes.push_back("P_nlv - P_nao is not above 0 before the peak flow: no pressure crossover");
  ph.ejection_start = ph.forward_flow_start;
  ph.ejection_start_condition = condition::forward_flow;
  auto later = [&](const char* name, double instant) {
    if (std::isnan(instant) || instant <= ph.ejection_start) return;
    if (instant >= ph.ejection_end) {
      notes.push_back(fmt::format("the {} ({}) comes after forward flow ends: it does not set t_bs", name,
                                  seconds(instant)));
      return;
    }
    ph.ejection_start = instant;
    ph.ejection_start_condition = name;
  };
  later(condition::pressure, ph.pressure_crossover);
  if (area_phases) later(condition::orifice, ph.opening_start);
}

/// The study's structural figures (docs/reference.md, "Hemodynamic metrics"): the leaflet-state
/// columns of a 3-D run read at the orifice phases' instants: fully opened (the fully open phase's
/// start), pre-close (its end) and fully closed (the closing phase's end, "just closed" for the
/// velocity). Nothing is added when the series has none of those columns.
void add_leaflet_state_metrics(const ValveSeries& w, const Phases& ph, const std::string& no_area, auto&& add)
{
  if (w.leaflet_state.empty()) return;
  struct State {
    const char* suffix;
    const char* symbol;
    const char* name;
    double time;
  };
  const State open{"open", "FO", "fully opened", ph.fully_open_start};
  const State preclose{"preclose", "PC", "pre-close", ph.fully_open_end};
  const State closed{"closed", "FC", "fully closed", ph.closing_end};
  // A column read at a state: scaled to the report unit; missing without the column or the instant.
  auto at_state = [&](const char* column, const State& state,
                      double scale) -> std::pair<std::optional<double>, std::string> {
    const auto c = w.leaflet_state.find(column);
    if (c == w.leaflet_state.end()) return {std::nullopt, fmt::format("no {} column", column)};
    if (!no_area.empty()) return {std::nullopt, no_area};
    if (std::isnan(state.time)) return {std::nullopt, fmt::format("no {} instant in the cycle", state.name)};
    return {scale * interpolate(w.t, c->second, state.time), "at t = " + seconds(state.time)};
  };
  auto metric = [&](std::string key, std::string symbol, const char* unit, std::string description,
                    const char* column, const State& state, double scale = 1.0) {
    auto [value, note] = at_state(column, state, scale);
    add(std::move(key), std::move(symbol), unit, std::move(description), value, note);
  };
  for (const State& s : {open, preclose, closed}) {
    metric(fmt::format("leaflet_displacement_mean_{}", s.suffix), fmt::format("d_mean,{}", s.symbol), "cm",
           fmt::format("mean leaflet displacement |x - X|, {}", s.name), column::displacement_mean, s);
    metric(fmt::format("leaflet_displacement_max_{}", s.suffix), fmt::format("d_max,{}", s.symbol), "cm",
           fmt::format("largest leaflet displacement |x - X|, {}", s.name), column::displacement_max, s);
  }
  for (const State& s : {open, closed})
    metric(
        fmt::format("peak_velocity_{}", s.suffix), fmt::format("u_max,{}", s.symbol), "m/s",
        fmt::format("peak velocity in the jet (largest fluid speed between the pressure probes), {}", s.name),
        column::peak_velocity, s, 1.0 / units::m_per_s);
  for (const State& s : {open, closed}) {
    metric(fmt::format("fiber_strain_belly_{}", s.suffix), fmt::format("E_ff,belly,{}", s.symbol), "1",
           fmt::format("fiber strain f0 . (E f0), belly spheres, {}", s.name), column::belly_fiber_strain, s);
    metric(fmt::format("fiber_strain_top_{}", s.suffix), fmt::format("E_ff,top,{}", s.symbol), "1",
           fmt::format("fiber strain f0 . (E f0), top-centre spheres, {}", s.name), column::top_fiber_strain,
           s);
    metric(fmt::format("fiber_stress_belly_{}", s.suffix), fmt::format("S_ff,belly,{}", s.symbol), "kPa",
           fmt::format("fiber stress f . (sigma f), belly spheres, {}", s.name), column::belly_fiber_stress,
           s);
    metric(fmt::format("fiber_stress_top_{}", s.suffix), fmt::format("S_ff,top,{}", s.symbol), "kPa",
           fmt::format("fiber stress f . (sigma f), top-centre spheres, {}", s.name),
           column::top_fiber_stress, s);
  }
  // The ranking's variations (docs/hemodynamics.md, "Comparison"): how far the belly and the
  // top-centre differ in the loaded, fully closed valve; the smaller, the more evenly the leaflet
  // carries its load.
  auto variation = [&](std::string key, std::string symbol, const char* unit, std::string description,
                       const char* belly, const char* top) {
    const auto [b, note] = at_state(belly, closed, 1.0);
    const auto [c, unused] = at_state(top, closed, 1.0);
    add(std::move(key), std::move(symbol), unit, std::move(description),
        b && c ? std::optional(std::abs(*b - *c)) : std::nullopt, note);
  };
  variation("strain_variation", "dE_ff", "1", "|belly - top-centre| fiber strain, fully closed",
            column::belly_fiber_strain, column::top_fiber_strain);
  variation("stress_variation", "dS_ff", "kPa", "|belly - top-centre| fiber stress, fully closed",
            column::belly_fiber_stress, column::top_fiber_stress);
}

/// The cycle `settings.cycle` asks for, counted from 0 (cycle k + 1 starts at t0 + k T), of the
/// `full_cycles` whole cycles the series holds; std::invalid_argument for a cycle it does not hold.
long chosen_cycle(const ValveSeries& series, const MetricSettings& settings, long& full_cycles)
{
  full_cycles = whole_cycles(series, settings.period);
  if (full_cycles < 1)
    throw std::invalid_argument(fmt::format("the series spans {:g} s, less than one period ({:g} s)",
                                            series.t.empty() ? 0.0 : series.t.back() - series.t.front(),
                                            settings.period));
  if (settings.cycle == 0 || settings.cycle < -1)
    throw std::invalid_argument(fmt::format(
        "cycle {}: cycles count from 1 (1 = the first, -1 = the last whole cycle)", settings.cycle));
  const long k = settings.cycle < 0 ? full_cycles - 1 : settings.cycle - 1;
  if (k >= full_cycles)
    throw std::invalid_argument(fmt::format("cycle {} asked for, but the series holds {} whole cycle(s)",
                                            settings.cycle, full_cycles));
  return k;
}

/// The orifice-area phases of the cycle `w` into `ph` (docs/hemodynamics.md, "Orifice phases"), and the
/// largest area, refined, into `area_max`. False when the series has no orifice area or it does not vary.
bool set_orifice_phases(const ValveSeries& w, const MetricSettings& settings, Phases& ph,
                        std::vector<std::string>& notes, double& area_max)
{
  if (!w.has_orifice_area()) return false;
  const std::vector<double>& t = w.t;
  const std::size_t n = t.size();
  const auto& area = w.orifice_area;
  const std::size_t i_hi = argmax(area, 0, n);
  area_max = refine_extreme(t, area, i_hi).value;
  const double a_max = area[i_hi];
  // Each side of the largest area is normalised by the closed state on its side: the opening by
  // the smallest area before it, the closing by the smallest after it. A dip of the leaflets just
  // before they open (pushed back by the ventricle's first contraction) would otherwise set the
  // closed level of the closing phase too, and the closing would end only when diastole creeps
  // down to that dip, or never (docs/hemodynamics.md, "Orifice phases").
  const double before_min = area[argmin(area, 0, i_hi + 1)];
  const double after_min = area[argmin(area, i_hi, n)];
  const auto varies = [&](double a_min) { return a_max - a_min > 1e-12 * std::max(1.0, std::abs(a_max)); };
  if (!varies(before_min) && !varies(after_min)) {
    notes.push_back("the orifice area does not vary: no opening/closing durations");
    return false;
  }
  // Already open at one end of the cycle: that side has no closed state of its own.
  const double opening_min = varies(before_min) ? before_min : after_min;
  const double closing_min = varies(after_min) ? after_min : before_min;
  std::vector<double> a(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double closed_area = i <= i_hi ? opening_min : closing_min;
    a[i] = (area[i] - closed_area) / (a_max - closed_area);
  }
  const double open = settings.open_area_fraction, closed = settings.closed_area_fraction;
  std::size_t i_open = 0;
  while (a[i_open] < open) ++i_open; // exists: a[i_hi] = 1
  std::size_t j = i_open;
  while (j > 0 && a[j - 1] > closed) --j;
  ph.opening_start = j == 0 ? t[0] : crossing(t, a, j - 1, closed);
  if (j == 0) notes.push_back("the orifice was already open at the start of the cycle");
  ph.fully_open_start = i_open == 0 ? t[0] : crossing(t, a, i_open - 1, open);
  std::size_t i_last = n - 1;
  while (a[i_last] < open) --i_last;
  ph.fully_open_end = i_last + 1 == n ? t[n - 1] : crossing(t, a, i_last, open);
  j = i_last;
  while (j + 1 < n && a[j + 1] > closed) ++j;
  if (j + 1 < n)
    ph.closing_end = crossing(t, a, j, closed);
  else
    notes.push_back("the orifice did not close within the cycle");
  return true;
}

/// The forward-flow lobe: the samples of Q above the threshold around the largest flow.
struct ForwardLobe {
  bool found = false;           // the largest flow is above the threshold
  std::size_t peak = 0;         // the largest flow's sample
  std::size_t after = 0;        // the first sample after the lobe (n when it reaches the cycle's end)
  Extreme largest;              // the largest flow, refined
  std::vector<double> gradient; // P_nlv - P_nao
};

/// The forward flow's phases into `ph`: t_ff, t_es, the peak, and t_bs (set_ejection_start).
ForwardLobe set_forward_phases(const ValveSeries& w, const MetricSettings& settings, bool area_phases,
                               Phases& ph, std::vector<std::string>& notes)
{
  const std::vector<double>& t = w.t;
  const std::vector<double>& q = w.valve_flow;
  const std::size_t n = t.size();
  const double threshold = settings.forward_threshold;
  ForwardLobe lobe;
  lobe.peak = argmax(q, 0, n);
  lobe.largest = refine_extreme(t, q, lobe.peak);
  lobe.found = q[lobe.peak] > threshold;
  lobe.gradient = combine(w.near_lv_pressure, w.near_aortic_pressure, std::minus<>());
  lobe.after = n;
  if (!lobe.found) {
    notes.push_back("no forward flow above the threshold in this cycle: ejection metrics are missing");
    return lobe;
  }
  ph.forward_flow_start = last_rise(t, q, lobe.peak, threshold);
  if (ph.forward_flow_start == t[0])
    notes.push_back("forward flow at the start of the cycle: t_ff is the cycle's start");
  std::size_t j = lobe.peak;
  while (j + 1 < n && q[j + 1] > threshold) ++j;
  ph.ejection_end = j + 1 == n ? t[n - 1] : crossing(t, q, j, threshold);
  if (j + 1 == n) notes.push_back("forward flow at the end of the cycle: t_es is the cycle's end");
  lobe.after = j + 1;
  ph.peak_forward_time = lobe.largest.time;
  set_ejection_start(t, lobe.gradient, lobe.peak, area_phases, ph, notes);
  return lobe;
}

/// The closure rule that applies: the one asked for, else the one the series allows (with a note why).
ClosureRule applicable_closure_rule(const MetricSettings& settings, bool area_phases, const Phases& ph,
                                    std::vector<std::string>& notes)
{
  ClosureRule rule = settings.closure_rule;
  if (rule == ClosureRule::automatic) rule = area_phases ? ClosureRule::area : ClosureRule::flow;
  if (rule == ClosureRule::area && !area_phases) {
    notes.push_back("closure rule 'area' asked for without a varying orifice area: the 'flow' rule is used");
    rule = ClosureRule::flow;
  }
  if (rule == ClosureRule::area && std::isnan(ph.closing_end)) {
    notes.push_back("the orifice did not close within the cycle: the 'flow' rule gives the closure");
    rule = ClosureRule::flow;
  }
  return rule;
}

/// t_c, the closure, into `ph` by `rule` (docs/hemodynamics.md); the backward flow's peak after
/// ejection is returned (time NaN when there is none).
Extreme set_closure(const ValveSeries& w, const MetricSettings& settings, const ForwardLobe& lobe,
                    ClosureRule rule, Phases& ph, std::vector<std::string>& notes)
{
  const std::vector<double>& t = w.t;
  const std::vector<double>& q = w.valve_flow;
  const std::size_t n = t.size();
  Extreme regurgitant_peak{nan, 0.0};
  if (lobe.after < n) {
    const std::size_t i_min = argmin(q, lobe.after, n);
    if (q[i_min] < 0.0) {
      regurgitant_peak = refine_extreme(t, q, i_min);
      ph.peak_regurgitant_time = regurgitant_peak.time;
    }
  }
  if (rule == ClosureRule::area) {
    ph.closure_rule = "area";
    ph.closure = ph.closing_end;
    if (ph.closure < ph.ejection_end) {
      notes.push_back("the orifice closed before forward flow ended: t_c is set to t_es (no closing volume)");
      ph.closure = ph.ejection_end;
    }
  } else {
    ph.closure_rule = "flow";
    if (std::isnan(regurgitant_peak.time)) {
      ph.closure = ph.ejection_end;
      notes.push_back("no backward flow after ejection: t_c = t_es");
    } else {
      const std::size_t i_min = argmin(q, lobe.after, n);
      const double leakage = q[n - 1];
      const double level = leakage + settings.closure_flow_fraction * (q[i_min] - leakage);
      std::size_t j = i_min;
      while (j + 1 < n && q[j + 1] < level) ++j;
      if (j + 1 < n) {
        ph.closure = crossing(t, q, j, level);
      } else {
        ph.closure = t[argmax(q, i_min, n)];
        notes.push_back("the backward flow never rose to the closure level: t_c is the time of the largest "
                        "flow after the regurgitant peak");
      }
    }
  }
  notes.push_back("phases: t_ff = " + seconds(ph.forward_flow_start) +
                  ", t_bs = " + seconds(ph.ejection_start) + " (" + ph.ejection_start_condition +
                  "), t_es = " + seconds(ph.ejection_end) + ", t_c = " + seconds(ph.closure) + " (rule '" +
                  ph.closure_rule + "')");
  return regurgitant_peak;
}

void add(ValveMetrics& out, std::string key, std::string symbol, std::string unit, std::string description,
         std::optional<double> value, std::string note = "")
{
  out.metrics.push_back(Metric{std::move(key), std::move(symbol), std::move(unit), std::move(description),
                               value, std::move(note)});
}

/// A peak's note names its own instant (inside the cycle), so that a value is never read against
/// another extreme's time.
std::string at(double time)
{
  return "at t = " + seconds(time);
}

/// The ejection's volumes and means (V_F, V_R, V_L, RF, TPG, Q_rms, EOA), and the ejection windows each
/// condition alone would open.
void add_ejection_metrics(ValveMetrics& out, const ValveSeries& w, const MetricSettings& settings,
                          const ForwardLobe& lobe, double t1)
{
  const std::vector<double>& t = w.t;
  const std::vector<double>& q = w.valve_flow;
  const Phases& ph = out.phases;
  std::optional<double> vf, vr, vl, rf, tpg, qrms, eoa;
  if (lobe.found) {
    vf = integrate(t, q, ph.forward_flow_start, ph.ejection_end);
    vr = -integrate(t, q, ph.ejection_end, ph.closure);
    vl = -integrate(t, q, ph.closure, t1);
    rf = (*vr + *vl) / *vf * 100.0;
    // The means over the chosen window, and over the window each condition alone would open.
    const auto q2 = combine(q, q, std::multiplies<>());
    auto window_from = [&](std::string condition, double start) {
      const double length = ph.ejection_end - start;
      EjectionWindow e{std::move(condition), start,
                       integrate(t, lobe.gradient, start, ph.ejection_end) / length,
                       std::sqrt(integrate(t, q2, start, ph.ejection_end) / length), std::nullopt};
      if (e.transvalvular_pressure_gradient > 0.0)
        e.effective_orifice_area =
            e.rms_forward_flow / (51.6 * std::sqrt(e.transvalvular_pressure_gradient / settings.density));
      return e;
    };
    const EjectionWindow chosen = window_from(ph.ejection_start_condition, ph.ejection_start);
    tpg = chosen.transvalvular_pressure_gradient;
    qrms = chosen.rms_forward_flow;
    eoa = chosen.effective_orifice_area;
    const std::pair<const char*, double> candidates[] = {{condition::forward_flow, ph.forward_flow_start},
                                                         {condition::pressure, ph.pressure_crossover},
                                                         {condition::orifice, ph.opening_start}};
    for (const auto& [name, start] : candidates)
      if (std::isfinite(start) && start < ph.ejection_end)
        out.ejection_windows.push_back(window_from(name, start));
  }
  const std::string no_ejection = lobe.found ? "" : "no forward ejection";
  add(out, "forward_volume", "V_F", "mL", "forward volume: the forward-flow lobe, t_ff to t_es", vf,
      no_ejection);
  add(out, "regurgitant_volume", "V_R", "mL", "closing regurgitant volume (end of ejection to closure)", vr,
      no_ejection);
  add(out, "leakage_volume", "V_L", "mL",
      "leakage volume: minus the integral of Q from closure t_c to the cycle's end", vl,
      vl && *vl < 0.0 ? "negative: net forward flow after closure" : no_ejection);
  add(out, "regurgitant_fraction", "RF", "%", "(V_R + V_L) / V_F", rf, no_ejection);
  add(out, "transvalvular_pressure_gradient", "TPG", "mmHg", "mean P_nlv - P_nao over ejection, t_bs to t_es",
      tpg, no_ejection);
  add(out, "rms_forward_flow", "Q_rms", "mL/s", "root mean square flow over ejection, t_bs to t_es", qrms,
      no_ejection);
  add(out, "effective_orifice_area", "EOA", "cm^2", "Q_rms / (51.6 sqrt(TPG / rho))", eoa,
      lobe.found && !eoa ? "TPG <= 0" : no_ejection);
}

/// Closed, as the IB method can measure it: the effective (hydraulic) orifice of the late-diastolic
/// leak, the largest |Q| over the cycle's last quarter divided by the Bernoulli jet velocity
/// sqrt(2 dp / rho) of the smallest closing pressure difference dp = P_nao - P_nlv there (an upper
/// bound on Q / v). A geometric gap narrower than the kernel's reach is sealed by the smeared
/// interface, so this, not the projected area, says whether the valve holds (docs/hemodynamics.md).
void add_diastolic_leak(ValveMetrics& out, const ValveSeries& w, const MetricSettings& settings, double t0,
                        double t1)
{
  const double late = t1 - 0.25 * (t1 - t0);
  double q_abs = 0.0, dp_min = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < w.t.size(); ++i)
    if (w.t[i] >= late) {
      q_abs = std::max(q_abs, std::abs(w.valve_flow[i]));
      dp_min = std::min(dp_min, w.near_aortic_pressure[i] - w.near_lv_pressure[i]);
    }
  const bool closing_pressure = dp_min > 0.0 && std::isfinite(dp_min);
  add(out, "diastolic_leak_area", "EROA_d", "cm^2",
      "late-diastolic leak orifice: max |Q| / sqrt(2 min(P_nao - P_nlv) / rho) over the cycle's last "
      "quarter",
      closing_pressure ? std::optional(q_abs / std::sqrt(2.0 * dp_min * units::mmHg / settings.density))
                       : std::nullopt,
      closing_pressure ? "" : "no closing pressure difference in late diastole");
}

/// The cycle's energy, peaks, pressures, leak and periodicity figures.
void add_cycle_metrics(ValveMetrics& out, const ValveSeries& w, const MetricSettings& settings,
                       const ForwardLobe& lobe, const Extreme& regurgitant_peak, double t0, double t1)
{
  const std::vector<double>& t = w.t;
  const std::vector<double>& q = w.valve_flow;
  const Phases& ph = out.phases;
  const std::string no_ejection = lobe.found ? "" : "no forward ejection";
  const auto dp_q =
      combine(combine(w.lv_pressure, w.aortic_pressure, std::minus<>()), q, std::multiplies<>());
  add(out, "energy_loss", "E_L", "mJ", "mmHg mL -> mJ times the integral of (P_LV - P_Ao) Q over the cycle",
      mmHg_mL_in_mJ() * integrate(t, dp_q, t0, t1));
  add(out, "peak_forward_flow", "Q_max", "mL/s", "largest forward flow in the cycle", lobe.largest.value,
      at(lobe.largest.time));
  add(out, "peak_regurgitant_flow", "Q_reg", "mL/s", "largest backward flow after ejection (positive)",
      std::isnan(regurgitant_peak.time) ? std::optional(0.0) : std::optional(-regurgitant_peak.value),
      std::isnan(regurgitant_peak.time) ? (lobe.found ? "no backward flow after ejection" : no_ejection)
                                        : at(regurgitant_peak.time));
  add(out, "ejection_duration", "T_ej", "ms", "t_es - t_bs",
      lobe.found ? std::optional((ph.ejection_end - ph.ejection_start) * 1e3) : std::nullopt, no_ejection);
  add(out, "net_volume", "V_net", "mL", "integral of Q over the cycle", integrate(t, q, t0, t1));
  add(out, "mean_aortic_pressure", "P_Ao,mean", "mmHg", "mean P_Ao over the cycle",
      integrate(t, w.aortic_pressure, t0, t1) / (t1 - t0));
  const std::size_t n = t.size();
  const std::size_t i_pao_max = argmax(w.aortic_pressure, 0, n), i_pao_min = argmin(w.aortic_pressure, 0, n);
  add(out, "systolic_aortic_pressure", "P_Ao,max", "mmHg", "largest P_Ao in the cycle",
      w.aortic_pressure[i_pao_max], at(t[i_pao_max]));
  add(out, "diastolic_aortic_pressure", "P_Ao,min", "mmHg", "smallest P_Ao in the cycle",
      w.aortic_pressure[i_pao_min], at(t[i_pao_min]));
  add_diastolic_leak(out, w, settings, t0, t1);
  // How periodic the cycle is: the Windkessel pressure at its two ends, and the volume it took in.
  if (!w.windkessel_pressure.empty()) {
    add(out, "windkessel_pressure_start", "P_Wk,0", "mmHg", "Windkessel pressure at the cycle's start",
        w.windkessel_pressure.front());
    add(out, "windkessel_pressure_end", "P_Wk,1", "mmHg", "Windkessel pressure at the cycle's end",
        w.windkessel_pressure.back());
  }
  if (!w.outlet_flow.empty())
    add(out, "outlet_volume", "V_out", "mL", "integral of the outlet flow over the cycle (against V_net)",
        integrate(t, w.outlet_flow, t0, t1));
}

/// The orifice's figures: its largest area and the durations of its phases.
void add_orifice_metrics(ValveMetrics& out, const ValveSeries& w, bool area_phases, double area_max,
                         const std::string& no_area)
{
  const Phases& ph = out.phases;
  add(out, "max_orifice_area", "GOA_max", "cm^2", "largest orifice area",
      w.has_orifice_area() ? std::optional(area_max) : std::nullopt, w.has_orifice_area() ? "" : no_area);
  auto ms = [](double a, double b) {
    return std::isnan(a) || std::isnan(b) ? std::nullopt : std::optional((b - a) * 1e3);
  };
  add(out, "opening_duration", "T_open", "ms", "orifice opening (closed -> fully open)",
      area_phases ? ms(ph.opening_start, ph.fully_open_start) : std::nullopt, area_phases ? "" : no_area);
  add(out, "fully_open_duration", "T_full", "ms", "orifice fully open",
      area_phases ? ms(ph.fully_open_start, ph.fully_open_end) : std::nullopt, area_phases ? "" : no_area);
  add(out, "closing_duration", "T_close", "ms", "orifice closing (fully open -> closed)",
      area_phases ? ms(ph.fully_open_end, ph.closing_end) : std::nullopt,
      area_phases ? (std::isnan(ph.closing_end) ? "did not close in the cycle" : "") : no_area);
}

} // namespace

ClosureRule closure_rule_from_name(const std::string& name)
{
  if (name == "auto") return ClosureRule::automatic;
  if (name == "flow") return ClosureRule::flow;
  if (name == "area") return ClosureRule::area;
  throw std::invalid_argument("unknown closure rule '" + name + "' (auto, flow, area)");
}

std::string closure_rule_name(ClosureRule rule)
{
  switch (rule) {
  case ClosureRule::automatic:
    return "auto";
  case ClosureRule::flow:
    return "flow";
  case ClosureRule::area:
    return "area";
  }
  return "?";
}

double mmHg_mL_in_mJ()
{
  return units::mmHg * units::mL / units::mJ;
}

const Metric* ValveMetrics::find(const std::string& key) const
{
  for (const Metric& m : metrics)
    if (m.key == key) return &m;
  return nullptr;
}

double ValveMetrics::value(const std::string& key) const
{
  const Metric* m = find(key);
  return m && m->value ? *m->value : nan;
}

int whole_cycles(const ValveSeries& series, double period)
{
  if (!(period > 0.0)) throw std::invalid_argument("period must be positive");
  if (series.t.empty()) return 0;
  const double span = series.t.back() - series.t.front();
  return static_cast<int>(std::floor(span / period * (1.0 + 1e-9)));
}

ValveMetrics compute_metrics(const ValveSeries& series, const MetricSettings& settings)
{
  long full_cycles = 0;
  const long k = chosen_cycle(series, settings, full_cycles);
  const double t0 = series.t.front() + static_cast<double>(k) * settings.period;
  const double t1 = std::min(t0 + settings.period, series.t.back());
  const ValveSeries w = time_window(series, t0, t1);

  ValveMetrics out;
  out.cycle = static_cast<int>(k + 1);
  out.cycles = static_cast<int>(full_cycles);
  Phases& ph = out.phases;
  ph.cycle_start = t0;
  ph.cycle_end = t1;
  out.notes.push_back(fmt::format("cycle {} of the {} whole cycle(s) in the series: [{}, {}], {} samples",
                                  out.cycle, out.cycles, seconds(t0), seconds(t1), w.t.size()));
  // The phases: the orifice's, the forward flow's, the closure's.
  double area_max = nan;
  const bool area_phases = set_orifice_phases(w, settings, ph, out.notes, area_max);
  const ForwardLobe lobe = set_forward_phases(w, settings, area_phases, ph, out.notes);
  const ClosureRule rule = applicable_closure_rule(settings, area_phases, ph, out.notes);
  Extreme regurgitant_peak{nan, 0.0};
  if (lobe.found) regurgitant_peak = set_closure(w, settings, lobe, rule, ph, out.notes);

  add_ejection_metrics(out, w, settings, lobe, t1);
  add_cycle_metrics(out, w, settings, lobe, regurgitant_peak, t0, t1);
  const std::string no_area = !w.has_orifice_area() ? "no orifice_area column" : "orifice area does not vary";
  add_orifice_metrics(out, w, area_phases, area_max, no_area);
  add_leaflet_state_metrics(w, ph, area_phases ? "" : no_area,
                            [&](std::string key, std::string symbol, std::string unit,
                                std::string description, std::optional<double> value, std::string note = "") {
                              add(out, std::move(key), std::move(symbol), std::move(unit),
                                  std::move(description), value, std::move(note));
                            });
  return out;
}

} // namespace ibvalve::hemodynamics
