// Metrics on synthetic valve series with closed-form answers (the definitions of docs/reference.md,
// "Hemodynamic metrics").
//
// One 0.8 s cycle, repeated: a half-sine forward ejection on [0.1, 0.4] s (400 mL/s), a half-sine
// closing backflow on [0.4, 0.46] s (80 mL/s), a half-sine leakage lobe over the rest of diastole
// (6 mL/s) and a short backflow lobe just before opening (8 mL/s). The lobes' slopes match where Q
// crosses zero (so the crossings are smooth, as a real flow's are). P_nlv - P_nao = 8 mmHg,
// P_LV - P_Ao = k Q, a trapezoidal orifice area that starts to open 4 ms before the flow turns forward
// (so the forward flow's start is the ejection's, t_bs). Every metric has a closed form; the series is
// sampled uniformly and non-uniformly with spacings up to ~2e-5 s, and the second cycle analysed.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <numbers>
#include <random>
#include <tuple>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "base/errors.hpp"
#include "hemodynamics/metrics.hpp"
#include "hemodynamics/timeseries.hpp"

namespace hd = ibvalve::hemodynamics;
using std::numbers::pi;

namespace {

constexpr double T = 0.8;
constexpr double t_bs = 0.1, D_f = 0.3, A_f = 400.0, t_es = t_bs + D_f;
constexpr double D_r = 0.06, A_r = A_f * D_r / D_f;  // slope matched at t_es
constexpr double d_p = 0.006, B_p = A_f * d_p / D_f; // slope matched at t_bs
constexpr double t_leak = t_es + D_r, D_L = T + t_bs - d_p - t_leak, B_L = 6.0;
constexpr double dP = 8.0, k_loss = 0.02;
constexpr double area_closed = 0.01, area_open_extra = 3.0, area_opens = t_bs - 0.004;

double flow(double t)
{
  const double tau = std::fmod(t, T);
  if (tau >= t_bs && tau < t_es) return A_f * std::sin(pi * (tau - t_bs) / D_f);
  if (tau >= t_es && tau < t_leak) return -A_r * std::sin(pi * (tau - t_es) / D_r);
  if (tau >= t_bs - d_p && tau < t_bs) return -B_p * std::sin(pi * (tau - (t_bs - d_p)) / d_p);
  const double s = tau >= t_leak ? tau - t_leak : tau + T - t_leak;
  return -B_L * std::sin(pi * s / D_L);
}

double area(double t)
{
  const double tau = std::fmod(t, T);
  double r = 0.0;
  if (tau >= area_opens && tau < area_opens + 0.04)
    r = (tau - area_opens) / 0.04;
  else if (tau >= area_opens + 0.04 && tau < 0.36)
    r = 1.0;
  else if (tau >= 0.36 && tau < 0.42)
    r = 1.0 - (tau - 0.36) / 0.06;
  return area_closed + area_open_extra * r;
}

hd::ValveSeries synthetic(const std::vector<double>& times, bool with_area)
{
  hd::ValveSeries s;
  for (double t : times) {
    const double q = flow(t);
    const double p_nao = 90.0 + 10.0 * std::sin(2 * pi * t / T), p_ao = 85.0 + 5.0 * std::cos(2 * pi * t / T);
    s.t.push_back(t);
    s.valve_flow.push_back(q);
    s.outlet_flow.push_back(q);
    s.near_aortic_pressure.push_back(p_nao);
    s.near_lv_pressure.push_back(p_nao + dP);
    s.aortic_pressure.push_back(p_ao);
    s.lv_pressure.push_back(p_ao + k_loss * q);
    s.windkessel_pressure.push_back(p_ao - 2.0);
    if (with_area) s.orifice_area.push_back(area(t));
  }
  return s;
}

std::vector<double> uniform(double h, double end = 2 * T)
{
  std::vector<double> t;
  const long n = std::lround(end / h);
  for (long i = 0; i <= n; ++i) t.push_back(end * static_cast<double>(i) / static_cast<double>(n));
  return t;
}

std::vector<double> jittered(double mean_h, unsigned seed, double end = 2 * T)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.5, 1.5);
  std::vector<double> t{0.0};
  while (t.back() + 1.5 * mean_h < end) t.push_back(t.back() + mean_h * u(rng));
  t.push_back(end);
  return t;
}

struct Expected {
  double vf, vr, vl, rf, tpg, qrms, eoa, el, qmax, qreg, t_c, net;
};

Expected expected(double closure_offset)
{
  // closure_offset: t_c - t_es within the backflow lobe.
  Expected e{};
  e.vf = 2 * A_f * D_f / pi;
  const double backward_total = 2 * A_r * D_r / pi + 2 * B_L * D_L / pi + 2 * B_p * d_p / pi;
  e.vr = A_r * D_r / pi * (1.0 - std::cos(pi * closure_offset / D_r));
  // V_L: from closure to the cycle's end, the rest of the backflow lobe and the leakage lobe up to t0 + T
  // (the part of that lobe before ejection, and the short lobe just before opening, are not leakage).
  e.vl = A_r * D_r / pi * (1.0 + std::cos(pi * closure_offset / D_r)) +
         B_L * D_L / pi * (1.0 - std::cos(pi * (T - t_leak) / D_L));
  e.net = e.vf - backward_total;
  e.rf = (e.vr + e.vl) / e.vf * 100;
  e.tpg = dP;
  e.qrms = A_f / std::sqrt(2.0);
  e.eoa = e.qrms / (51.6 * std::sqrt(dP / 1.0));
  e.el = hd::mmHg_mL_in_mJ() * k_loss *
         (A_f * A_f * D_f / 2 + A_r * A_r * D_r / 2 + B_L * B_L * D_L / 2 + B_p * B_p * d_p / 2);
  e.qmax = A_f;
  e.qreg = A_r;
  e.t_c = T + t_es + closure_offset;
  return e;
}

/// Rule "flow": t_c - t_es where the backflow lobe has recovered to Q_end + f (Q_min - Q_end), with
/// Q_end the leakage flow at the end of the analysed (second) cycle.
double flow_rule_offset(double f)
{
  const double q_end = flow(2 * T);
  const double level = q_end + f * (-A_r - q_end);
  return D_r * (1.0 - std::asin(-level / A_r) / pi);
}

void expect_relative(double value, double exact, double tolerance, const std::string& what)
{
  EXPECT_LE(std::abs(value - exact), tolerance * std::abs(exact)) << what << ": " << value << " vs " << exact;
}

void check_all(const hd::ValveMetrics& m, const Expected& e, const std::string& label)
{
  const double tol = 1e-6;
  expect_relative(m.value("forward_volume"), e.vf, tol, label + " V_F");
  expect_relative(m.value("regurgitant_volume"), e.vr, tol, label + " V_R");
  expect_relative(m.value("leakage_volume"), e.vl, tol, label + " V_L");
  expect_relative(m.value("regurgitant_fraction"), e.rf, tol, label + " RF");
  expect_relative(m.value("transvalvular_pressure_gradient"), e.tpg, tol, label + " TPG");
  expect_relative(m.value("rms_forward_flow"), e.qrms, tol, label + " Q_rms");
  expect_relative(m.value("effective_orifice_area"), e.eoa, tol, label + " EOA");
  expect_relative(m.value("energy_loss"), e.el, tol, label + " E_L");
  expect_relative(m.value("peak_forward_flow"), e.qmax, tol, label + " peak forward");
  expect_relative(m.value("peak_regurgitant_flow"), e.qreg, tol, label + " peak regurgitant");
  expect_relative(m.value("ejection_duration"), D_f * 1e3, tol, label + " ejection duration");
  expect_relative(m.value("net_volume"), e.net, 1e-5, label + " net volume");
  expect_relative(m.value("outlet_volume"), e.net, 1e-5, label + " outlet volume"); // Q_outlet = Q here
  expect_relative(m.value("windkessel_pressure_start"), 85.0 + 5.0 - 2.0, 1e-9, label + " P_Wk at t0");
  expect_relative(m.value("windkessel_pressure_end"), 85.0 + 5.0 - 2.0, 1e-9, label + " P_Wk at t0 + T");
  // Each peak's note names its own instant: the ejection's crest and the closing backflow's.
  EXPECT_EQ(m.find("peak_forward_flow")->note, fmt::format("at t = {:.4f} s", T + t_bs + D_f / 2)) << label;
  EXPECT_EQ(m.find("peak_regurgitant_flow")->note, fmt::format("at t = {:.4f} s", T + t_es + D_r / 2))
      << label;
  // P_nlv - P_nao = 8 mmHg all through this series: no closing pressure, so no leak orifice.
  EXPECT_FALSE(m.find("diastolic_leak_area")->value) << label;
  expect_relative(m.phases.ejection_start, T + t_bs, 1e-8, label + " t_bs");
  expect_relative(m.phases.ejection_end, T + t_es, 1e-8, label + " t_es");
  expect_relative(m.phases.closure, e.t_c, 1e-8, label + " t_c");
}

} // namespace

TEST(Metrics, FlowClosureRuleMatchesClosedFormsForAnySampling)
{
  hd::MetricSettings settings; // the default rule is "flow"
  EXPECT_EQ(settings.closure_rule, hd::ClosureRule::flow);
  const Expected e = expected(flow_rule_offset(settings.closure_flow_fraction));
  for (const auto& [label, times] :
       std::vector<std::pair<std::string, std::vector<double>>>{{"uniform 1e-5", uniform(1e-5)},
                                                                {"uniform 2e-5", uniform(2e-5)},
                                                                {"non-uniform 1.5e-5", jittered(1.5e-5, 7)},
                                                                {"non-uniform 1e-5", jittered(1e-5, 11)}}) {
    const hd::ValveMetrics m = hd::compute_metrics(synthetic(times, false), settings);
    check_all(m, e, label);
    EXPECT_EQ(m.phases.closure_rule, "flow");
    EXPECT_FALSE(m.find("opening_duration")->value); // no area column: reported missing
    EXPECT_FALSE(m.find("opening_duration")->note.empty());
  }
}

TEST(Metrics, TheLateDiastolicLeakOrificeIsTheLeakOverTheBernoulliVelocity)
{
  // A 0.8 s cycle: ejection, then a steady leak of 0.5 mL/s against P_nao - P_nlv = 80 mmHg (60 mmHg
  // in the last 50 ms, the smallest difference of the cycle's last quarter).
  hd::ValveSeries s;
  for (double t : uniform(1e-4, T)) {
    const bool ejecting = t > 0.1 && t < 0.4;
    s.t.push_back(t);
    s.valve_flow.push_back(ejecting ? 300.0 * std::sin(pi * (t - 0.1) / 0.3) : -0.5);
    s.lv_pressure.push_back(ejecting ? 100.0 : 5.0);
    s.aortic_pressure.push_back(ejecting ? 95.0 : 85.0);
    s.near_lv_pressure.push_back(ejecting ? 100.0 : 5.0);
    s.near_aortic_pressure.push_back(ejecting ? 95.0 : (t > 0.75 ? 65.0 : 85.0));
  }
  const hd::ValveMetrics m = hd::compute_metrics(s, hd::MetricSettings{});
  const double v = std::sqrt(2.0 * 60.0 * 1333.22 / 1.0); // cm/s
  expect_relative(m.value("diastolic_leak_area"), 0.5 / v, 1e-12, "EROA_d");
  EXPECT_FALSE(m.find("windkessel_pressure_start")); // no such columns: no such metrics
  EXPECT_FALSE(m.find("outlet_volume"));
}

TEST(Metrics, AreaRuleAndOrificeDurationsMatchClosedForms)
{
  hd::MetricSettings settings;
  settings.closure_rule = hd::ClosureRule::automatic; // picks "area": the series has an orifice area
  const double closing_end = 0.36 + (1.0 - settings.closed_area_fraction) * 0.06;
  const Expected e = expected(closing_end - t_es);
  for (const auto& [label, times] : std::vector<std::pair<std::string, std::vector<double>>>{
           {"uniform 1e-5", uniform(1e-5)}, {"non-uniform 1.5e-5", jittered(1.5e-5, 3)}}) {
    const hd::ValveMetrics m = hd::compute_metrics(synthetic(times, true), settings);
    EXPECT_EQ(m.phases.closure_rule, "area");
    check_all(m, e, label);
    expect_relative(m.value("opening_duration"), (0.9 - 0.05) * 0.04 * 1e3, 1e-6, label + " opening");
    expect_relative(m.value("fully_open_duration"), (0.36 + 0.1 * 0.06 - (area_opens + 0.9 * 0.04)) * 1e3,
                    1e-6, label + " fully open");
    expect_relative(m.value("closing_duration"), (0.95 - 0.1) * 0.06 * 1e3, 1e-6, label + " closing");
    expect_relative(m.value("max_orifice_area"), area_closed + area_open_extra, 1e-12, label + " max area");
  }
}

TEST(Metrics, EachOrificePhaseIsJudgedAgainstTheClosedStateOnItsSide)
{
  // The series above with the leaflets pushed back just before they open: the area dips to
  // area_closed - depth over [0.05, 0.09] s, below its diastolic level. The closing is normalised by
  // the smallest area after the largest, so it ends as without the dip; the opening by the smallest
  // before it, the dip. (With one minimum for the cycle the diastolic level sits at
  // depth / (extra + depth) = 0.09 > closed_area_fraction and the orifice never closes.)
  constexpr double depth = 0.3, dip_start = 0.05, dip_length = 0.04;
  hd::MetricSettings settings;
  const double closed = settings.closed_area_fraction, open = settings.open_area_fraction;
  hd::ValveSeries s = synthetic(uniform(1e-5), true);
  for (std::size_t i = 0; i < s.t.size(); ++i) {
    const double tau = std::fmod(s.t[i], T) - dip_start;
    if (tau >= 0.0 && tau < dip_length) s.orifice_area[i] -= depth * std::sin(pi * tau / dip_length);
  }
  const hd::ValveMetrics m = hd::compute_metrics(s, settings);

  const double a_min = area_closed - depth, range = area_closed + area_open_extra - a_min;
  // Opening: a = closed on the dip's way back up, where depth sin(phase) = area_closed - a_min - closed range
  // with the phase past its middle; a = open on the ramp, area_closed + extra r = a_min + open range.
  const double phase = pi - std::asin((area_closed - (a_min + closed * range)) / depth);
  const double opening_start = dip_start + dip_length * phase / pi;
  const double fully_open_start = area_opens + 0.04 * (a_min + open * range - area_closed) / area_open_extra;
  expect_relative(m.value("opening_duration"), (fully_open_start - opening_start) * 1e3, 1e-6, "opening");
  expect_relative(m.value("fully_open_duration"), (0.36 + (1.0 - open) * 0.06 - fully_open_start) * 1e3, 1e-6,
                  "fully open");
  expect_relative(m.value("closing_duration"), (open - closed) * 0.06 * 1e3, 1e-6, "closing");
}

TEST(Metrics, TrapezoidalErrorsFallAtSecondOrder)
{
  // Coarse samplings: the error of the integrals falls as h^2 (the measured figure behind the
  // sampling advice in docs/hemodynamics.md). (E_L is not used here: the trapezoidal rule is exact to
  // round-off for the sin^2 lobes of Q^2.)
  hd::MetricSettings settings;
  settings.closure_rule = hd::ClosureRule::flow;
  const Expected e = expected(flow_rule_offset(settings.closure_flow_fraction));
  std::vector<double> errors_vr, errors_vf;
  for (double h : {8e-4, 4e-4, 2e-4, 1e-4}) {
    const auto m = hd::compute_metrics(synthetic(uniform(h), false), settings);
    errors_vr.push_back(std::abs(m.value("regurgitant_volume") / e.vr - 1));
    errors_vf.push_back(std::abs(m.value("forward_volume") / e.vf - 1));
  }
  for (std::size_t i = 1; i < errors_vr.size(); ++i) {
    const double order_vr = std::log2(errors_vr[i - 1] / errors_vr[i]);
    const double order_vf = std::log2(errors_vf[i - 1] / errors_vf[i]);
    std::cout << "  V_R rel. error " << errors_vr[i] << " (order " << order_vr << "), V_F rel. error "
              << errors_vf[i] << " (order " << order_vf << ")\n";
    EXPECT_GT(order_vr, 1.8);
    EXPECT_GT(order_vf, 1.8);
  }
}

TEST(Metrics, CycleSelectionAndMissingEjection)
{
  hd::MetricSettings settings;
  settings.cycle = 1; // cycles count from 1: the first
  const auto m0 = hd::compute_metrics(synthetic(uniform(1e-4), false), settings);
  EXPECT_NEAR(m0.phases.cycle_start, 0.0, 1e-15);
  EXPECT_NEAR(m0.phases.ejection_start, t_bs, 1e-7);
  EXPECT_EQ(m0.cycle, 1);
  EXPECT_EQ(m0.cycles, 2);
  settings.cycle = 2; // the second, which the last whole one (-1) is too
  const auto m1 = hd::compute_metrics(synthetic(uniform(1e-4), false), settings);
  EXPECT_NEAR(m1.phases.cycle_start, settings.period, 1e-12);
  settings.cycle = -1;
  EXPECT_EQ(hd::compute_metrics(synthetic(uniform(1e-4), false), settings).phases.cycle_start,
            m1.phases.cycle_start);
  settings.cycle = 0; // no cycle 0
  EXPECT_THROW(hd::compute_metrics(synthetic(uniform(1e-4), false), settings), std::invalid_argument);
  settings.cycle = 3;
  EXPECT_THROW(hd::compute_metrics(synthetic(uniform(1e-4), false), settings), std::invalid_argument);
  settings.cycle = -1;
  settings.period = 2.0;
  EXPECT_THROW(hd::compute_metrics(synthetic(uniform(1e-4), false), settings), std::invalid_argument);
  // A valve that never opens: ejection metrics are missing (with a note), E_L is still defined.
  hd::ValveSeries closed = synthetic(uniform(1e-4), false);
  for (double& q : closed.valve_flow) q = -std::abs(q) - 1.0;
  const auto m = hd::compute_metrics(closed, hd::MetricSettings{});
  EXPECT_FALSE(m.find("forward_volume")->value);
  EXPECT_FALSE(m.find("effective_orifice_area")->value);
  EXPECT_TRUE(m.find("energy_loss")->value);
}

TEST(Metrics, ReadsTimeseriesCsvAndRejectsBadFiles)
{
  const auto dir = std::filesystem::temp_directory_path() / "ibvalve_test_metrics";
  std::filesystem::create_directories(dir);
  const auto s = synthetic(uniform(1e-5), true);
  {
    std::ofstream out(dir / "timeseries.csv");
    out << std::setprecision(17);
    const auto names = hd::standard_columns();
    for (std::size_t c = 0; c < names.size(); ++c) out << (c ? "," : "") << names[c];
    out << "\n";
    for (std::size_t i = 0; i < s.size(); ++i)
      out << s.t[i] << "," << s.valve_flow[i] << "," << s.outlet_flow[i] << "," << s.lv_pressure[i] << ","
          << s.aortic_pressure[i] << "," << s.windkessel_pressure[i] << "," << s.near_lv_pressure[i] << ","
          << s.near_aortic_pressure[i] << "," << s.orifice_area[i] << "\n";
  }
  const auto read = hd::read_valve_series(dir / "timeseries.csv");
  const auto direct = hd::compute_metrics(s, {});
  const auto from_file = hd::compute_metrics(read, {});
  for (const auto& metric : direct.metrics)
    if (metric.value) {
      EXPECT_DOUBLE_EQ(*metric.value, from_file.value(metric.key)) << metric.key;
    }
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return dir / name;
  };
  EXPECT_THROW(hd::read_valve_series(write("a.csv", "t,Q_valve,P_LV,P_Ao,P_nlv\n0,1,2,3,4\n")),
               ibvalve::InputError);
  EXPECT_THROW(
      hd::read_valve_series(write("b.csv", "t,Q_valve,P_LV,P_Ao,P_nlv,P_nao\n0,1,2,3,4,5\n0.1,1,x,3,4,5\n")),
      ibvalve::InputError);
  EXPECT_THROW(hd::read_valve_series(write(
                   "c.csv", "t,Q_valve,P_LV,P_Ao,P_nlv,P_nao\n0,1,2,3,4,5\n0,1,2,3,4,5\n0.2,1,2,3,4,5\n")),
               ibvalve::InputError);
  EXPECT_THROW(hd::read_valve_series(dir / "none.csv"), ibvalve::InputError);
  std::filesystem::remove_all(dir);
}

TEST(Metrics, IntegrationAndWindowsAreExactForLinearData)
{
  const std::vector<double> t{0.0, 0.1, 0.25, 0.7, 1.0};
  std::vector<double> y;
  for (double x : t) y.push_back(3.0 * x - 1.0);
  // Integral of 3x - 1 over [0.05, 0.9] = 1.5 (b^2 - a^2) - (b - a).
  EXPECT_NEAR(hd::integrate(t, y, 0.05, 0.9), 1.5 * (0.81 - 0.0025) - 0.85, 1e-14);
  EXPECT_NEAR(hd::integrate(t, y, 0.9, 0.05), -(1.5 * (0.81 - 0.0025) - 0.85), 1e-14);
  EXPECT_NEAR(hd::interpolate(t, y, 0.4), 0.2, 1e-14);
  hd::ValveSeries s;
  s.t = t;
  for (auto* c :
       {&s.valve_flow, &s.lv_pressure, &s.aortic_pressure, &s.near_lv_pressure, &s.near_aortic_pressure})
    *c = y;
  const auto w = hd::time_window(s, 0.05, 0.9);
  ASSERT_EQ(w.t.size(), 5u);
  EXPECT_DOUBLE_EQ(w.t.front(), 0.05);
  EXPECT_DOUBLE_EQ(w.t.back(), 0.9);
  EXPECT_NEAR(w.valve_flow.back(), 1.7, 1e-14);
  EXPECT_TRUE(w.outlet_flow.empty());
}

// The leaflet-state columns of a 3-D run, linear in t so that the values at the orifice phases'
// instants are exact: fully opened (a reaches 0.9 at area_opens + 0.9 x 0.04 s), pre-close (a leaves 0.9 at
// 0.36 + 0.1 x 0.06 s) and fully closed (a falls to 0.05 at 0.36 + 0.95 x 0.06 s), in the second cycle.
TEST(Metrics, LeafletStateIsReadAtTheFullyOpenedPreCloseAndFullyClosedInstants)
{
  const std::vector<std::pair<std::string, std::pair<double, double>>> linear{
      {hd::column::displacement_mean, {0.1, 0.5}}, {hd::column::displacement_max, {0.3, 1.5}},
      {hd::column::peak_velocity, {50.0, 200.0}},  {hd::column::belly_fiber_strain, {0.01, 0.1}},
      {hd::column::top_fiber_strain, {0.02, 0.3}}, {hd::column::belly_fiber_stress, {5.0, 40.0}},
      {hd::column::top_fiber_stress, {1.0, 90.0}}};
  auto value = [&](const char* column, double t) {
    for (const auto& [name, ab] : linear)
      if (name == column) return ab.first + ab.second * t;
    return std::nan("");
  };
  const auto times = jittered(2e-4, 5);
  hd::ValveSeries s = synthetic(times, true);
  for (const auto& [name, ab] : linear)
    for (double t : times) s.leaflet_state[name].push_back(ab.first + ab.second * t);
  const hd::ValveMetrics m = hd::compute_metrics(s, {});
  const double open = T + area_opens + 0.9 * 0.04, preclose = T + 0.36 + 0.1 * 0.06,
               closed = T + 0.36 + 0.95 * 0.06;
  const std::vector<std::tuple<std::string, const char*, double, double>> cases{
      {"leaflet_displacement_mean_open", hd::column::displacement_mean, open, 1.0},
      {"leaflet_displacement_mean_preclose", hd::column::displacement_mean, preclose, 1.0},
      {"leaflet_displacement_mean_closed", hd::column::displacement_mean, closed, 1.0},
      {"leaflet_displacement_max_open", hd::column::displacement_max, open, 1.0},
      {"leaflet_displacement_max_preclose", hd::column::displacement_max, preclose, 1.0},
      {"leaflet_displacement_max_closed", hd::column::displacement_max, closed, 1.0},
      {"peak_velocity_open", hd::column::peak_velocity, open, 0.01}, // cm/s -> m/s
      {"peak_velocity_closed", hd::column::peak_velocity, closed, 0.01},
      {"fiber_strain_belly_open", hd::column::belly_fiber_strain, open, 1.0},
      {"fiber_strain_top_closed", hd::column::top_fiber_strain, closed, 1.0},
      {"fiber_stress_belly_closed", hd::column::belly_fiber_stress, closed, 1.0},
      {"fiber_stress_top_open", hd::column::top_fiber_stress, open, 1.0}};
  for (const auto& [key, column, t, scale] : cases) {
    ASSERT_TRUE(m.find(key)) << key;
    expect_relative(m.value(key), scale * value(column, t), 1e-9, key);
    EXPECT_NE(m.find(key)->note.find(fmt::format("at t = {:.4f} s", t)), std::string::npos) << key;
  }
  expect_relative(
      m.value("strain_variation"),
      std::abs(value(hd::column::belly_fiber_strain, closed) - value(hd::column::top_fiber_strain, closed)),
      1e-9, "strain variation");
  expect_relative(
      m.value("stress_variation"),
      std::abs(value(hd::column::belly_fiber_stress, closed) - value(hd::column::top_fiber_stress, closed)),
      1e-9, "stress variation");

  // Without an orifice area the instants are unknown: the metrics are there, missing, with the reason.
  hd::ValveSeries no_area = s;
  no_area.orifice_area.clear();
  const hd::ValveMetrics without = hd::compute_metrics(no_area, {});
  ASSERT_TRUE(without.find("fiber_strain_belly_open"));
  EXPECT_FALSE(without.find("fiber_strain_belly_open")->value);
  EXPECT_EQ(without.find("strain_variation")->note, "no orifice_area column");
  // A run without leaflet-state columns (lumped, older 3-D series) gets none of these metrics.
  EXPECT_FALSE(hd::compute_metrics(synthetic(times, true), {}).find("strain_variation"));

  // timeseries.csv with the columns reads them back.
  const auto dir = std::filesystem::temp_directory_path() / "ibvalve_test_leaflet_state";
  std::filesystem::create_directories(dir);
  {
    std::ofstream out(dir / "timeseries.csv");
    out << std::setprecision(17) << "t,Q_valve,P_LV,P_Ao,P_nlv,P_nao,orifice_area";
    for (const auto& name : hd::leaflet_state_columns()) out << "," << name;
    out << "\n";
    for (std::size_t i = 0; i < s.size(); ++i) {
      out << s.t[i] << "," << s.valve_flow[i] << "," << s.lv_pressure[i] << "," << s.aortic_pressure[i] << ","
          << s.near_lv_pressure[i] << "," << s.near_aortic_pressure[i] << "," << s.orifice_area[i];
      for (const auto& name : hd::leaflet_state_columns()) out << "," << s.leaflet_state.at(name)[i];
      out << "\n";
    }
  }
  const hd::ValveMetrics read = hd::compute_metrics(hd::read_valve_series(dir / "timeseries.csv"), {});
  EXPECT_DOUBLE_EQ(read.value("stress_variation"), m.value("stress_variation"));
  EXPECT_DOUBLE_EQ(read.value("leaflet_displacement_max_preclose"),
                   m.value("leaflet_displacement_max_preclose"));
  std::filesystem::remove_all(dir);
}

namespace {

// A cycle whose closed leaflets bulge before they open: forward flow through the flow plane from
// 0.05 s, the pressure across the leaflets turning forward at 0.08 s and the orifice opening from
// 0.1 s; forward flow ends at 0.4 s. Q = A sin(pi (tau - 0.05) / 0.35) over [0.05, 0.4], a backflow lobe
// after it, P_nlv - P_nao = G(tau) = slope (tau - 0.08) up to 0.12 s, then 20 mmHg until 0.4 s, then
// -40 mmHg; the orifice area ramps from closed to open over [0.1, 0.14] s.
constexpr double bulge_start = 0.05, bulge_flow_end = 0.4, bulge_amplitude = 400.0;
constexpr double crossover = 0.08, gradient_slope = 500.0, gradient_plateau = 20.0;
constexpr double orifice_opens = 0.1, orifice_ramp = 0.04;

double bulge_gradient(double tau)
{
  if (tau < 0.12) return gradient_slope * (tau - crossover);
  return tau < bulge_flow_end ? gradient_plateau : -40.0;
}

hd::ValveSeries bulging_leaflets(const std::vector<double>& times, bool with_area)
{
  hd::ValveSeries s;
  for (double t : times) {
    const double tau = std::fmod(t, T);
    const double length = bulge_flow_end - bulge_start;
    double q = tau < bulge_start ? 0.0 : -1.0; // no flow, then the bulge: Q is continuous at t_ff
    if (tau >= bulge_start && tau < bulge_flow_end)
      q = bulge_amplitude * std::sin(pi * (tau - bulge_start) / length);
    else if (tau >= bulge_flow_end && tau < bulge_flow_end + 0.06)
      q = -60.0 * std::sin(pi * (tau - bulge_flow_end) / 0.06);
    s.t.push_back(t);
    s.valve_flow.push_back(q);
    s.near_aortic_pressure.push_back(80.0);
    s.near_lv_pressure.push_back(80.0 + bulge_gradient(tau));
    s.aortic_pressure.push_back(80.0);
    s.lv_pressure.push_back(80.0 + bulge_gradient(tau));
    if (with_area) {
      const double r = std::clamp((tau - orifice_opens) / orifice_ramp, 0.0, 1.0) *
                       (tau < 0.36 ? 1.0 : std::max(0.0, 1.0 - (tau - 0.36) / 0.06));
      s.orifice_area.push_back(0.1 + 2.0 * r);
    }
  }
  return s;
}

/// TPG, Q_rms and EOA of bulging_leaflets over [start, bulge_flow_end] of a cycle, in closed form.
std::tuple<double, double, double> bulge_means(double start)
{
  const double end = bulge_flow_end, length = end - bulge_start;
  const double gradient_integral =
      gradient_slope / 2 * (std::pow(0.12 - crossover, 2) - std::pow(start - crossover, 2)) +
      gradient_plateau * (end - 0.12);
  // int sin^2(pi (tau - t_ff) / L) = (tau - t_ff) / 2 - L / (4 pi) sin(2 pi (tau - t_ff) / L)
  auto sin2 = [&](double tau) {
    return (tau - bulge_start) / 2 - length / (4 * pi) * std::sin(2 * pi * (tau - bulge_start) / length);
  };
  const double tpg = gradient_integral / (end - start);
  const double qrms = bulge_amplitude * std::sqrt((sin2(end) - sin2(start)) / (end - start));
  return {tpg, qrms, qrms / (51.6 * std::sqrt(tpg))};
}

} // namespace

TEST(Metrics, DisplacementFlowBeforeTheValveOpensIsNotEjection)
{
  // Under the rule of forward flow alone, t_bs was 0.05 s: the TPG then averaged the 30 ms of closed,
  // bulging leaflets held shut by a backward pressure difference. Now the window opens when the valve
  // does: at the orifice's opening (area past closed_area_fraction) with an area, at the pressure
  // crossover without one. V_F still counts the whole forward-flow lobe.
  hd::MetricSettings settings;
  const double area_crossing = orifice_opens + settings.closed_area_fraction * orifice_ramp;
  const double vf = 2 * bulge_amplitude * (bulge_flow_end - bulge_start) / pi;
  for (const bool with_area : {true, false}) {
    const std::string label = with_area ? "with an orifice area" : "without one";
    const hd::ValveMetrics m = hd::compute_metrics(bulging_leaflets(uniform(1e-5), with_area), settings);
    const double start = with_area ? area_crossing : crossover;
    expect_relative(m.phases.forward_flow_start, T + bulge_start, 1e-8, label + " t_ff");
    expect_relative(m.phases.pressure_crossover, T + crossover, 1e-8, label + " crossover");
    expect_relative(m.phases.ejection_start, T + start, 1e-8, label + " t_bs");
    EXPECT_EQ(m.phases.ejection_start_condition, with_area ? "orifice opening" : "pressure crossover")
        << label;
    expect_relative(m.phases.ejection_end, T + bulge_flow_end, 1e-8, label + " t_es");
    const auto [tpg, qrms, eoa] = bulge_means(start);
    expect_relative(m.value("transvalvular_pressure_gradient"), tpg, 1e-6, label + " TPG");
    expect_relative(m.value("rms_forward_flow"), qrms, 1e-6, label + " Q_rms");
    expect_relative(m.value("effective_orifice_area"), eoa, 1e-6, label + " EOA");
    expect_relative(m.value("ejection_duration"), (bulge_flow_end - start) * 1e3, 1e-6, label + " T_ej");
    expect_relative(m.value("forward_volume"), vf, 1e-6, label + " V_F");

    // Each condition's own window, with its means: how far the figures depend on the rule.
    ASSERT_EQ(m.ejection_windows.size(), with_area ? 3u : 2u) << label;
    for (const hd::EjectionWindow& w : m.ejection_windows) {
      const double expected_start = w.condition == "forward flow"         ? bulge_start
                                    : w.condition == "pressure crossover" ? crossover
                                                                          : area_crossing;
      expect_relative(w.start, T + expected_start, 1e-8, label + " " + w.condition);
      if (expected_start < crossover) {
        // From t_ff the window holds the backward gradient of the closed leaflets: a lower mean.
        EXPECT_LT(w.transvalvular_pressure_gradient, tpg) << label;
        continue;
      }
      const auto [w_tpg, w_qrms, w_eoa] = bulge_means(expected_start);
      expect_relative(w.transvalvular_pressure_gradient, w_tpg, 1e-6, label + " " + w.condition + " TPG");
      expect_relative(w.rms_forward_flow, w_qrms, 1e-6, label + " " + w.condition + " Q_rms");
      ASSERT_TRUE(w.effective_orifice_area) << label;
      expect_relative(*w.effective_orifice_area, w_eoa, 1e-6, label + " " + w.condition + " EOA");
    }
  }
}

TEST(Metrics, AnOpeningAfterForwardFlowEndsDoesNotSetTheEjectionStart)
{
  // An orifice that opens only after the forward flow has ended (over [0.45, 0.49] s, closing over
  // [0.6, 0.66] s): it cannot start the ejection, t_bs is the pressure crossover, and a note says why.
  hd::ValveSeries s = bulging_leaflets(uniform(1e-4), true);
  for (std::size_t i = 0; i < s.t.size(); ++i) {
    const double tau = std::fmod(s.t[i], T);
    s.orifice_area[i] = 0.1 + 2.0 * std::clamp((tau - 0.45) / 0.04, 0.0, 1.0) *
                                  std::clamp(1.0 - (tau - 0.6) / 0.06, 0.0, 1.0);
  }
  const hd::ValveMetrics m = hd::compute_metrics(s, hd::MetricSettings{});
  EXPECT_GT(m.phases.opening_start, m.phases.ejection_end);
  expect_relative(m.phases.ejection_start, T + crossover, 1e-8, "t_bs");
  EXPECT_EQ(m.phases.ejection_start_condition, "pressure crossover");
  EXPECT_EQ(m.ejection_windows.size(), 2u); // no window from an opening after the flow's end
  bool noted = false;
  for (const std::string& note : m.notes)
    noted = noted || (note.find("orifice opening") != std::string::npos &&
                      note.find("after forward flow ends") != std::string::npos);
  EXPECT_TRUE(noted);
}
