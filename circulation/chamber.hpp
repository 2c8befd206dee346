#pragma once
// A heart chamber as a time-varying elastance (Regazzoni, Salvador, Africa, Fedele, Dedè & Quarteroni
// 2022, J. Comput. Phys. 457:111083, the lumped circulation of their Appendix; docs/circulation.md):
//
//   p(t, V) = E(t) (V - V_0),   E(t) = E_B + E_A e(t),
//
// with the activation e(t) in [0, 1] a raised cosine that rises over the contraction [t_C, t_C + T_C]
// and falls over the relaxation [t_C + T_C, t_C + T_C + T_R], both taken modulo the heartbeat period T:
//
//   e = (1 - cos(pi s / T_C)) / 2,   s = (t - t_C) mod T in [0, T_C),
//   e = (1 + cos(pi r / T_R)) / 2,   r = (t - t_C - T_C) mod T in [0, T_R),
//   e = 0 otherwise.
//
// The times t_C, T_C, T_R are kept as fractions of the heartbeat (as the reference implementation
// gives them), so a change of heart rate scales the beat's phases with it.
//
// e(t) is C^1 (its slope vanishes at the three switching times) with jumps in its second derivative,
// which matters for the order of a time integrator (circulation/closed_loop.hpp). CGS throughout.

namespace ibvalve::circulation {

struct ChamberParameters {
  double active_elastance = 0.0;  // E_A, dyn/cm^5
  double passive_elastance = 0.0; // E_B, dyn/cm^5
  double rest_volume = 0.0;       // V_0, cm^3 (the volume at zero pressure)
  double contraction_start = 0.0; // t_C / T, from the start of a beat
  double contraction_time = 0.0;  // T_C / T
  double relaxation_time = 0.0;   // T_R / T

  /// e(t) for a heartbeat of `period` s.
  double activation(double t, double period) const;
  /// E(t) = E_B + E_A e(t).
  double elastance(double t, double period) const
  {
    return passive_elastance + active_elastance * activation(t, period);
  }
  /// p = E(t) (V - V_0).
  double pressure(double t, double period, double volume) const
  {
    return elastance(t, period) * (volume - rest_volume);
  }
  /// Throws std::invalid_argument (naming `chamber`) unless E_A >= 0, E_B > 0, T_C > 0, T_R > 0 and
  /// T_C + T_R <= T.
  void check(const char* chamber) const;
};

} // namespace ibvalve::circulation
