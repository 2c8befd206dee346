#pragma once
// The 0-D (lumped) valve between a driving LV pressure and the three-element Windkessel.
//
// Valve (Mynard, Davidson, Penny & Smolich 2012, Int J Numer Meth Biomed Eng 28:626): a state
// zeta in [0, 1] sets the effective orifice area A = (A_max - A_min) zeta + A_min, with
// A_max = M_st A_ann, A_min = M_rg A_ann; the flow obeys Bernoulli with inertance,
//   dp = B Q|Q| + L dQ/dt,  B = rho / (2 A^2),  L = rho l_eff / A,  dp = P_LV - P_Ao,
// and zeta opens or closes at rates proportional to the pressure difference,
//   dzeta/dt = (1 - zeta) K_vo (dp - dp_open)   when dp > dp_open,
//   dzeta/dt = zeta K_vc (dp - dp_close)         when dp < dp_close.
// Outlet: C dP_Wk/dt = Q - (P_Wk - P_d)/R_p, P_Ao = P_Wk + R_c Q (windkessel/windkessel.hpp). The
// three states (Q, zeta, P_Wk) advance together by classical Runge–Kutta 4 with a fixed step. The ODE
// keeps zeta in [0, 1] but an RK4 stage may step past an end, so zeta is clamped in the right-hand side
// and after each step. Everything is CGS.
#include <array>

#include "windkessel/waveform.hpp"
#include "windkessel/windkessel.hpp"

namespace ibvalve::windkessel {

struct ValveParameters {
  double annulus_area = 0.0;    // A_ann, cm^2
  double max_area_fraction = 0; // M_st
  double min_area_fraction = 0; // M_rg
  double effective_length = 0;  // l_eff, cm
  double opening_rate = 0;      // K_vo, 1/(dyn/cm^2 s)
  double closing_rate = 0;      // K_vc, 1/(dyn/cm^2 s)
  double opening_pressure = 0;  // dp_open, dyn/cm^2
  double closing_pressure = 0;  // dp_close, dyn/cm^2
  double density = 0;           // rho, g/cm^3

  /// The effective orifice area A(zeta), cm^2.
  double area(double zeta) const
  {
    return annulus_area * ((max_area_fraction - min_area_fraction) * zeta + min_area_fraction);
  }
  /// (dQ/dt, dzeta/dt) for the pressure difference dp = upstream - downstream across the valve, the
  /// flow q and the state zeta (clamped to [0, 1]): the valve's own equations above, for any circuit
  /// that places it between two pressures (this file's LumpedSystem, circulation/closed_loop.hpp).
  std::array<double, 2> rates(double dp, double q, double zeta) const;
};

/// The valve driven by `lv_pressure` and loaded by `outlet` (whose parameters and right-hand side are
/// used; its own state is not touched). Both must outlive the system.
struct LumpedSystem {
  using State = std::array<double, 3>; // Q (cm^3/s), zeta, P_Wk (dyn/cm^2)
  const PeriodicWaveform& lv_pressure;
  const ThreeElementWindkessel& outlet;
  ValveParameters valve;

  /// P_Ao = P_Wk + R_c Q.
  double aortic_pressure(const State& y) const
  {
    return y[2] + outlet.parameters().proximal_resistance * y[0];
  }
  /// dy/dt at time t.
  State rate(double t, const State& y) const;
  /// One classical Runge–Kutta 4 step from (t, y) to t + dt.
  State step(double t, const State& y, double dt) const;
};

} // namespace ibvalve::windkessel
