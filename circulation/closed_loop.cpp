#include "circulation/closed_loop.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "base/units.hpp"

namespace ibvalve::circulation {

double DiodeValve::flow(double upstream_pressure, double downstream_pressure) const
{
  const double dp = upstream_pressure - downstream_pressure;
  const double step = 0.5 + std::atan(0.5 * std::numbers::pi * switch_slope * -dp) / std::numbers::pi;
  const double log_r =
      std::log10(open_resistance) + (std::log10(closed_resistance) - std::log10(open_resistance)) * step;
  return dp / std::pow(10.0, log_r);
}

void CirculationParameters::check() const
{
  if (!(heart_rate > 0.0)) throw std::invalid_argument("circulation: the heart rate must be > 0");
  left_atrium.check("left atrium");
  left_ventricle.check("left ventricle");
  right_atrium.check("right atrium");
  right_ventricle.check("right ventricle");
  for (const DiodeValve* v : {&mitral, &aortic, &tricuspid, &pulmonary})
    if (!(v->open_resistance > 0.0) || !(v->closed_resistance > v->open_resistance) ||
        !(v->switch_slope > 0.0))
      throw std::invalid_argument("circulation: a valve needs 0 < R_min < R_max and a positive switch slope");
  for (const Compartment* c : {&systemic_arterial, &systemic_venous, &pulmonary_arterial, &pulmonary_venous})
    if (!(c->compliance > 0.0) || !(c->resistance > 0.0) || !(c->inertance > 0.0))
      throw std::invalid_argument("circulation: a compartment needs positive C, R and L");
  if (aortic_kind == AorticValveKind::orifice) {
    const windkessel::ValveParameters& v = aortic_orifice;
    if (!(v.annulus_area > 0.0) || !(v.min_area_fraction > 0.0) ||
        !(v.max_area_fraction > v.min_area_fraction) || !(v.effective_length > 0.0) || !(v.density > 0.0))
      throw std::invalid_argument(
          "circulation: the orifice aortic valve needs positive areas, length and density");
  }
}

CirculationParameters regazzoni2022()
{
  // Values as the reference implementation writes them (mmHg, mL, s; timings as fractions of the
  // heartbeat at 72 beats/min), converted to CGS. docs/circulation.md, "Parameters", gives the source.
  const double elastance = units::mmHg / units::mL, resistance = units::mmHg / units::mL;
  const double compliance = units::mL / units::mmHg, inertance = units::mmHg / units::mL;
  CirculationParameters p;
  p.heart_rate = 72.0 * units::per_minute;
  auto chamber = [&](double e_a, double e_b, double v0, double t_c, double tc, double tr) {
    return ChamberParameters{e_a * elastance, e_b * elastance, v0 * units::mL, t_c, tc, tr};
  };
  p.left_atrium = chamber(0.07, 0.09, 4.0, 0.80, 0.17, 0.17);
  p.left_ventricle = chamber(2.75, 0.08, 5.0, 0.00, 0.34, 0.17);
  p.right_atrium = chamber(0.06, 0.07, 4.0, 0.80, 0.17, 0.17);
  p.right_ventricle = chamber(0.55, 0.05, 10.0, 0.00, 0.34, 0.17);
  const DiodeValve valve{0.0075 * resistance, 75006.2 * resistance, 200.0 / units::mmHg};
  p.mitral = p.aortic = p.tricuspid = p.pulmonary = valve;
  p.systemic_arterial = {1.2 * compliance, 0.8 * resistance, 5.0e-3 * inertance};
  p.systemic_venous = {60.0 * compliance, 0.26 * resistance, 5.0e-4 * inertance};
  p.pulmonary_arterial = {10.0 * compliance, 0.1625 * resistance, 5.0e-4 * inertance};
  p.pulmonary_venous = {16.0 * compliance, 0.1625 * resistance, 5.0e-4 * inertance};
  return p;
}

ClosedLoop::ClosedLoop(const CirculationParameters& parameters) : parameters_(parameters)
{
  parameters_.check();
  names_ = {"V_LA",     "V_LV",      "V_RA",     "V_RV",      "p_AR_SYS", "p_VEN_SYS",
            "p_AR_PUL", "p_VEN_PUL", "Q_AR_SYS", "Q_VEN_SYS", "Q_AR_PUL", "Q_VEN_PUL"};
  if (parameters_.aortic_kind == AorticValveKind::orifice) {
    names_.push_back("Q_AV");
    names_.push_back("zeta_AV");
  }
  for (State& s : stages_) s.assign(names_.size(), 0.0);
}

std::optional<std::size_t> ClosedLoop::index(std::string_view name) const
{
  const auto it = std::find(names_.begin(), names_.end(), name);
  if (it == names_.end()) return std::nullopt;
  return static_cast<std::size_t>(it - names_.begin());
}

ClosedLoop::State ClosedLoop::initial_state() const
{
  // The reference implementation's initial state (docs/circulation.md), in mL, mmHg and mL/s.
  State y(names_.size(), 0.0);
  y[V_LA] = 65.0 * units::mL;
  y[V_LV] = 120.0 * units::mL;
  y[V_RA] = 65.0 * units::mL;
  y[V_RV] = 145.0 * units::mL;
  y[p_AR_SYS] = 80.0 * units::mmHg;
  y[p_VEN_SYS] = 30.0 * units::mmHg;
  y[p_AR_PUL] = 35.0 * units::mmHg;
  y[p_VEN_PUL] = 24.0 * units::mmHg;
  return y; // flows start at rest, the orifice valve closed
}

Derived ClosedLoop::derived(double t, std::span<const double> y) const
{
  const CirculationParameters& p = parameters_;
  const double T = period();
  Derived d;
  d.p_LA = p.left_atrium.pressure(t, T, y[V_LA]);
  d.p_LV = p.left_ventricle.pressure(t, T, y[V_LV]);
  d.p_RA = p.right_atrium.pressure(t, T, y[V_RA]);
  d.p_RV = p.right_ventricle.pressure(t, T, y[V_RV]);
  d.Q_MV = p.mitral.flow(d.p_LA, d.p_LV);
  d.Q_AV = p.aortic_kind == AorticValveKind::orifice ? y[Q_AV_state] : p.aortic.flow(d.p_LV, y[p_AR_SYS]);
  d.Q_TV = p.tricuspid.flow(d.p_RA, d.p_RV);
  d.Q_PV = p.pulmonary.flow(d.p_RV, y[p_AR_PUL]);
  return d;
}

void ClosedLoop::rate(double t, std::span<const double> y, std::span<double> dydt,
                      const ExternalAorticFlow* external) const
{
  const CirculationParameters& p = parameters_;
  const Derived d = derived(t, y);
  const double leaving_ventricle = external ? external->ventricle(t) : d.Q_AV;
  const double entering_arteries = external ? external->arteries(t) : d.Q_AV;
  dydt[V_LA] = y[Q_VEN_PUL] - d.Q_MV;
  dydt[V_LV] = d.Q_MV - leaving_ventricle;
  dydt[V_RA] = y[Q_VEN_SYS] - d.Q_TV;
  dydt[V_RV] = d.Q_TV - d.Q_PV;
  dydt[p_AR_SYS] = (entering_arteries - y[Q_AR_SYS]) / p.systemic_arterial.compliance;
  dydt[p_VEN_SYS] = (y[Q_AR_SYS] - y[Q_VEN_SYS]) / p.systemic_venous.compliance;
  dydt[p_AR_PUL] = (d.Q_PV - y[Q_AR_PUL]) / p.pulmonary_arterial.compliance;
  dydt[p_VEN_PUL] = (y[Q_AR_PUL] - y[Q_VEN_PUL]) / p.pulmonary_venous.compliance;
  auto line = [](const Compartment& c, double p_in, double p_out, double q) {
    return (p_in - p_out - c.resistance * q) / c.inertance;
  };
  dydt[Q_AR_SYS] = line(p.systemic_arterial, y[p_AR_SYS], y[p_VEN_SYS], y[Q_AR_SYS]);
  dydt[Q_VEN_SYS] = line(p.systemic_venous, y[p_VEN_SYS], d.p_RA, y[Q_VEN_SYS]);
  dydt[Q_AR_PUL] = line(p.pulmonary_arterial, y[p_AR_PUL], y[p_VEN_PUL], y[Q_AR_PUL]);
  dydt[Q_VEN_PUL] = line(p.pulmonary_venous, y[p_VEN_PUL], d.p_LA, y[Q_VEN_PUL]);
  if (p.aortic_kind == AorticValveKind::orifice) {
    // An outside aortic valve leaves the orifice's own state where it is.
    const auto [dq, dzeta] = external
                                 ? std::array<double, 2>{0.0, 0.0}
                                 : p.aortic_orifice.rates(d.p_LV - y[p_AR_SYS], y[Q_AV_state], y[zeta_AV]);
    dydt[Q_AV_state] = dq;
    dydt[zeta_AV] = dzeta;
  }
}

void ClosedLoop::step(double t, State& y, double dt, const ExternalAorticFlow* external) const
{
  auto& [k1, k2, k3, k4, stage] = stages_;
  const std::size_t n = y.size();
  auto at = [&](const State& k, double h) {
    for (std::size_t i = 0; i < n; ++i) stage[i] = y[i] + h * k[i];
    return std::span<const double>(stage);
  };
  rate(t, y, k1, external);
  rate(t + 0.5 * dt, at(k1, 0.5 * dt), k2, external);
  rate(t + 0.5 * dt, at(k2, 0.5 * dt), k3, external);
  rate(t + dt, at(k3, dt), k4, external);
  for (std::size_t i = 0; i < n; ++i) y[i] += dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
  if (parameters_.aortic_kind == AorticValveKind::orifice) y[zeta_AV] = std::clamp(y[zeta_AV], 0.0, 1.0);
}

double ClosedLoop::total_volume(std::span<const double> y) const
{
  const CirculationParameters& p = parameters_;
  return y[V_LA] + y[V_LV] + y[V_RA] + y[V_RV] + p.systemic_arterial.compliance * y[p_AR_SYS] +
         p.systemic_venous.compliance * y[p_VEN_SYS] + p.pulmonary_arterial.compliance * y[p_AR_PUL] +
         p.pulmonary_venous.compliance * y[p_VEN_PUL];
}

} // namespace ibvalve::circulation
