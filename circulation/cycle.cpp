#include "circulation/cycle.hpp"

#include <algorithm>
#include <cmath>

namespace ibvalve::circulation {

CycleRecorder::CycleRecorder(const ClosedLoop& loop, double t, std::span<const double> y)
    : loop_(loop), start_(y.begin(), y.end()), last_(start_), lowest_(start_), highest_(start_),
      lv_peak_(loop.derived(t, y).p_LV)
{
}

void CycleRecorder::add(double t, std::span<const double> y)
{
  for (std::size_t i = 0; i < y.size(); ++i) {
    lowest_[i] = std::min(lowest_[i], y[i]);
    highest_[i] = std::max(highest_[i], y[i]);
  }
  last_.assign(y.begin(), y.end());
  lv_peak_ = std::max(lv_peak_, loop_.derived(t, y).p_LV);
}

CycleFigures CycleRecorder::figures() const
{
  CycleFigures f;
  f.end_diastolic_volume = highest_[V_LV];
  f.end_systolic_volume = lowest_[V_LV];
  f.stroke_volume = f.end_diastolic_volume - f.end_systolic_volume;
  f.ejection_fraction = f.stroke_volume / f.end_diastolic_volume;
  f.lv_peak_pressure = lv_peak_;
  f.aortic_systolic = highest_[p_AR_SYS];
  f.aortic_diastolic = lowest_[p_AR_SYS];
  f.state_change.resize(last_.size());
  for (std::size_t i = 0; i < last_.size(); ++i) {
    f.state_change[i] = last_[i] - start_[i];
    const double swing = highest_[i] - lowest_[i];
    if (swing > 0.0) f.periodicity_error = std::max(f.periodicity_error, std::abs(f.state_change[i]) / swing);
  }
  return f;
}

CycleFigures run_cycle(const ClosedLoop& loop, double t0, ClosedLoop::State& y, long steps)
{
  const double dt = loop.period() / static_cast<double>(steps);
  CycleRecorder recorder(loop, t0, y);
  for (long n = 0; n < steps; ++n) {
    const double t = t0 + static_cast<double>(n) * dt;
    loop.step(t, y, dt);
    recorder.add(t + dt, y);
  }
  return recorder.figures();
}

} // namespace ibvalve::circulation
