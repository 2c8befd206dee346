#pragma once
// FFTW plans across a restart. The fluid solvers' transforms are planned by timing candidates
// (-fluid_fftw_planner measure, the default), and two processes may choose different plans, which
// differ in round-off. A run therefore records the plans its solvers chose (some are made at the
// first step) in <run>/fftw_wisdom.txt with every checkpoint; a restart loads them before it builds
// its solver, so it computes with the interrupted run's transforms and continues it bit for bit.
#include "app/model.hpp"

namespace ibvalve::app {

/// On a restart: loads <run>/fftw_wisdom.txt when there is one (call before building the fluid solver).
void load_fftw_plans(const RunContext& context);
/// Writes the plans chosen so far to <run>/fftw_wisdom.txt (with each checkpoint). Collective.
void save_fftw_plans(const RunContext& context);

} // namespace ibvalve::app
