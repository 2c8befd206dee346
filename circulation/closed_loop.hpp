#pragma once
// The closed-loop lumped circulation of Regazzoni, Salvador, Africa, Fedele, Dedè & Quarteroni (2022),
// J. Comput. Phys. 457:111083 (arXiv:2011.15040), its 0-D model of the whole circulation
// (docs/circulation.md gives the equations, the parameters and where each number comes from):
//
//   four chambers, p_i = E_i(t) (V_i - V_0,i)  (circulation/chamber.hpp), i = LA, LV, RA, RV;
//   four valves as resistive diodes, Q = (p_up - p_down) / R(p_up, p_down),
//     log10 R = log10 R_min + (log10 R_max - log10 R_min) H(p_down - p_up),
//     H(x) = 1/2 + atan(pi/2 k x) / pi  (a smoothed step of slope k per mmHg);
//   the systemic (SYS) and pulmonary (PUL) arterial (AR) and venous (VEN) compartments, each a
//     compliance C (pressure p, volume C p) followed by a resistance R and an inertance L:
//       C_AR^SYS dp_AR^SYS/dt = Q_AV - Q_AR^SYS,   L_AR^SYS dQ_AR^SYS/dt = p_AR^SYS - p_VEN^SYS - R_AR^SYS
//       Q_AR^SYS, C_VEN^SYS dp_VEN^SYS/dt = Q_AR^SYS - Q_VEN^SYS,  L_VEN^SYS dQ_VEN^SYS/dt = p_VEN^SYS - p_RA
//       - R_VEN^SYS Q_VEN^SYS,
//     and the same for PUL from the pulmonary valve to the left atrium;
//   dV_LA/dt = Q_VEN^PUL - Q_MV, dV_LV/dt = Q_MV - Q_AV, dV_RA/dt = Q_VEN^SYS - Q_TV, dV_RV/dt = Q_TV - Q_PV.
//
// The aortic valve may instead be the 0-D orifice valve of windkessel/lumped_valve.hpp (Mynard et al.
// 2012), adding its flow Q_AV and opening zeta_AV to the state, so a valve's area can be changed.
//
// Every flow leaves one volume and enters another, so the total blood volume
//   V_tot = V_LA + V_LV + V_RA + V_RV + C_AR^SYS p_AR^SYS + C_VEN^SYS p_VEN^SYS + C_AR^PUL p_AR^PUL +
//   C_VEN^PUL p_VEN^PUL
// (the chambers' volumes include their V_0; the compartments of this model have no unstressed volume)
// has a zero rate. A Runge–Kutta method conserves a linear invariant exactly, so V_tot is kept to
// round-off. Time stepping: classical Runge–Kutta 4 with a fixed step (order 4 when the step divides
// the activations' switching times, whose second derivatives jump; docs/circulation.md measures it).
// Everything is CGS.
#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "circulation/chamber.hpp"
#include "windkessel/lumped_valve.hpp"

namespace ibvalve::circulation {

/// A valve as a resistive diode between two pressures.
struct DiodeValve {
  double open_resistance = 0.0;   // R_min, dyn s/cm^5
  double closed_resistance = 0.0; // R_max, dyn s/cm^5
  double switch_slope = 0.0;      // k of H(x) = 1/2 + atan(pi/2 k x)/pi, per dyn/cm^2

  /// Q = (p_up - p_down) / R(p_up, p_down), cm^3/s.
  double flow(double upstream_pressure, double downstream_pressure) const;
};

/// A compartment: compliance C, then resistance R and inertance L to the next one.
struct Compartment {
  double compliance = 0.0; // C, cm^5/dyn
  double resistance = 0.0; // R, dyn s/cm^5
  double inertance = 0.0;  // L, g/cm^4
};

enum class AorticValveKind { diode, orifice };

struct CirculationParameters {
  double heart_rate = 0.0; // beats per second (the case file writes beats per minute)
  ChamberParameters left_atrium, left_ventricle, right_atrium, right_ventricle;
  DiodeValve mitral, aortic, tricuspid, pulmonary;
  Compartment systemic_arterial, systemic_venous, pulmonary_arterial, pulmonary_venous;
  AorticValveKind aortic_kind = AorticValveKind::diode;
  windkessel::ValveParameters aortic_orifice; // used when aortic_kind == orifice

  /// Throws std::invalid_argument when a value is out of range.
  void check() const;
};

/// The parameter set named "regazzoni2022" (docs/circulation.md, "Parameters", for each number's source).
CirculationParameters regazzoni2022();

/// The state's entries, in order; the orifice aortic valve appends Q_AV and zeta_AV.
enum Entry : std::size_t {
  V_LA,
  V_LV,
  V_RA,
  V_RV,
  p_AR_SYS,
  p_VEN_SYS,
  p_AR_PUL,
  p_VEN_PUL,
  Q_AR_SYS,
  Q_VEN_SYS,
  Q_AR_PUL,
  Q_VEN_PUL,
  Q_AV_state,
  zeta_AV,
};

/// What the state implies at one instant: the chambers' pressures and the valves' flows (CGS).
struct Derived {
  double p_LA = 0, p_LV = 0, p_RA = 0, p_RV = 0;
  double Q_MV = 0, Q_AV = 0, Q_TV = 0, Q_PV = 0;
};

/// The aortic valve replaced by a model outside the loop (a 3-D valve in its tube): over one step
/// [t, t + dt] the flow leaving the left ventricle and the flow entering the systemic arteries, each
/// linear in time from its start to its end value (cm^3/s). The two differ by what the outside model
/// stores or loses (a compliant tube, a leak), so V_tot changes by the integral of their difference.
struct ExternalAorticFlow {
  double t = 0.0, dt = 0.0;
  double ventricle_start = 0.0, ventricle_end = 0.0; // leaving the LV
  double arteries_start = 0.0, arteries_end = 0.0;   // entering the systemic arteries
  double ventricle(double s) const
  {
    return ventricle_start + (ventricle_end - ventricle_start) * fraction(s);
  }
  double arteries(double s) const { return arteries_start + (arteries_end - arteries_start) * fraction(s); }
  double fraction(double s) const { return dt > 0.0 ? (s - t) / dt : 0.0; }
};

class ClosedLoop {
 public:
  using State = std::vector<double>;

  explicit ClosedLoop(const CirculationParameters& parameters);

  const CirculationParameters& parameters() const { return parameters_; }
  /// The heartbeat T = 1 / heart rate, s.
  double period() const { return 1.0 / parameters_.heart_rate; }
  /// The names of the state's entries ("V_LA", ..., "Q_VEN_PUL"[, "Q_AV", "zeta_AV"]), by which a
  /// checkpoint saves and restores it.
  const std::vector<std::string>& state_names() const { return names_; }
  std::size_t size() const { return names_.size(); }
  /// The index of a named entry, or nullopt.
  std::optional<std::size_t> index(std::string_view name) const;

  /// The initial state of the reference implementation (docs/circulation.md, "Initial state").
  State initial_state() const;
  /// The chambers' pressures and the valves' flows at time t.
  Derived derived(double t, std::span<const double> y) const;
  /// dy/dt at time t; with `external` the aortic valve's flows are its (the diode's are not used).
  void rate(double t, std::span<const double> y, std::span<double> dydt,
            const ExternalAorticFlow* external = nullptr) const;
  /// One classical Runge–Kutta 4 step from (t, y) to t + dt, in place; with `external` (its t and dt
  /// those of the step) the aortic valve is the outside model's. Uses this object's scratch stages: one
  /// caller at a time.
  void step(double t, State& y, double dt, const ExternalAorticFlow* external = nullptr) const;
  /// V_tot, cm^3 (the invariant above).
  double total_volume(std::span<const double> y) const;

 private:
  CirculationParameters parameters_;
  std::vector<std::string> names_;
  mutable std::array<State, 5> stages_; // k1..k4 and the stage state, reused by step()
};

} // namespace ibvalve::circulation
