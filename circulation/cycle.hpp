#pragma once
// One heartbeat of the closed loop summarized: the left ventricle's end-diastolic and end-systolic
// volumes (its largest and smallest volume over the beat, as in an elastance model's pressure-volume
// loop), stroke volume and ejection fraction, peak LV pressure, systolic and diastolic aortic (systemic
// arterial) pressure, and how far the state is from periodic: each entry's change over the beat.
#include <span>
#include <vector>

#include "circulation/closed_loop.hpp"

namespace ibvalve::circulation {

struct CycleFigures {
  double end_diastolic_volume = 0;  // EDV, cm^3
  double end_systolic_volume = 0;   // ESV, cm^3
  double stroke_volume = 0;         // EDV - ESV, cm^3
  double ejection_fraction = 0;     // SV / EDV
  double lv_peak_pressure = 0;      // dyn/cm^2
  double aortic_systolic = 0;       // max p_AR^SYS, dyn/cm^2
  double aortic_diastolic = 0;      // min p_AR^SYS, dyn/cm^2
  std::vector<double> state_change; // y(end) - y(start), per state entry (CGS)
  /// max over the entries of |y_i(end) - y_i(start)| / (max y_i - min y_i over the beat): 0 for a
  /// periodic state.
  double periodicity_error = 0;
};

/// Collects one beat's figures from the states a run passes through.
class CycleRecorder {
 public:
  CycleRecorder(const ClosedLoop& loop, double t, std::span<const double> y);
  /// The state at time t within the beat (each step's end).
  void add(double t, std::span<const double> y);
  /// The figures, the last state added being the beat's end.
  CycleFigures figures() const;

 private:
  const ClosedLoop& loop_;
  std::vector<double> start_, last_, lowest_, highest_;
  double lv_peak_ = 0;
};

/// Advances `y` from t0 by one heartbeat in `steps` Runge–Kutta 4 steps and returns its figures.
CycleFigures run_cycle(const ClosedLoop& loop, double t0, ClosedLoop::State& y, long steps);

} // namespace ibvalve::circulation
