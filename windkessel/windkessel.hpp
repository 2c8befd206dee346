#pragma once
// The three-element Windkessel outlet (Westerhof et al. 1971; parameters of Stergiopulos et al. 1999):
//
//   C dP_Wk/dt + (P_Wk - P_d) / R_p = Q_Ao,      P_Ao = P_Wk + R_c Q_Ao,
//
// Q_Ao the flow leaving through the outlet, P_d the distal (venous) pressure. Everything is in CGS
// (dyn/cm^2, cm^3/s, dyn s/cm^5, cm^5/dyn); the case file takes mmHg s/mL, mL/mmHg and mmHg.
//
// Time stepping: the ODE is linear, so with Q taken linear in time over a step it is integrated
// exactly (exponential integration): the result is unconditionally stable (the decay factor
// exp(-dt/(R_p C)) lies in (0, 1) for every dt) and second-order accurate in dt for a smooth Q, the
// only error being the linear interpolation of Q. See docs/windkessel.md.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ibvalve::windkessel {

/// Parameters in CGS.
struct WindkesselParameters {
  double proximal_resistance = 0.0; // R_c, dyn s/cm^5
  double distal_resistance = 0.0;   // R_p, dyn s/cm^5
  double compliance = 0.0;          // C, cm^5/dyn
  double distal_pressure = 0.0;     // P_d, dyn/cm^2
  double initial_pressure = 0.0;    // P_Wk(0), dyn/cm^2

  /// R_p C, the decay time of the reservoir, s.
  double time_constant() const { return distal_resistance * compliance; }
  /// Throws std::invalid_argument when a resistance or the compliance is not positive.
  void check() const;
};

/// A named parameter set; "stergiopulos-typeA" is the human Type A beat of Stergiopulos et al. (1999)
/// used by the reference study (docs/reference.md, "Boundary conditions"): R_c 0.033 mmHg s/mL,
/// R_p 0.79 mmHg s/mL, C 1.75 mL/mmHg, P_d 0, P_Wk(0) 85 mmHg.
std::optional<WindkesselParameters> preset(std::string_view name);
std::vector<std::string> preset_names();

/// The state of the outlet, enough to restart it exactly (checkpoints, predictor-corrector coupling).
struct WindkesselState {
  double time = 0.0;
  double reservoir_pressure = 0.0; // P_Wk, dyn/cm^2
  double flow = 0.0;               // Q_Ao at `time`, cm^3/s
};

class ThreeElementWindkessel {
 public:
  /// Starts at P_Wk = initial_pressure with the outlet flow `start_flow` (the start of the first
  /// step's linear flow when advance(dt, flow_end) is used).
  explicit ThreeElementWindkessel(const WindkesselParameters& parameters, double start_time = 0.0,
                                  double start_flow = 0.0);

  const WindkesselParameters& parameters() const { return parameters_; }
  const WindkesselState& state() const { return state_; }
  void restore(const WindkesselState& state) { state_ = state; }

  double time() const { return state_.time; }
  /// P_Wk now.
  double reservoir_pressure() const { return state_.reservoir_pressure; }
  /// P_Ao = P_Wk + R_c Q for the flow last given (the start flow before the first step).
  double outlet_pressure() const { return outlet_pressure(state_.flow); }
  /// P_Ao = P_Wk + R_c Q for a given outlet flow Q at the current time.
  double outlet_pressure(double flow) const
  {
    return state_.reservoir_pressure + parameters_.proximal_resistance * flow;
  }

  /// Advances by dt with the outlet flow varying linearly from the last flow given to `flow_end`;
  /// returns P_Ao at the end of the step. This is the coupled run's call: give Q_Ao, get P_Ao.
  double advance(double dt, double flow_end) { return advance(dt, state_.flow, flow_end); }
  /// Advances by dt with the outlet flow linear from `flow_start` to `flow_end`; returns P_Ao(t + dt).
  double advance(double dt, double flow_start, double flow_end);

  /// P_Wk after a step of dt with linear flow, without changing the state (for iterated couplings).
  double reservoir_pressure_after(double dt, double flow_start, double flow_end) const;
  /// dP_Wk/dt for a reservoir pressure and an outlet flow (the right-hand side of the ODE), for
  /// callers that integrate the Windkessel inside a larger ODE system.
  double reservoir_rate(double reservoir_pressure, double flow) const;

 private:
  WindkesselParameters parameters_;
  WindkesselState state_;
};

} // namespace ibvalve::windkessel
