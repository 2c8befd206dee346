#pragma once
// FFTW plans across a restart. The fluid solvers' transforms are planned by timing candidates
// (-fluid_fftw_planner measure, the default), and two processes may choose different plans, which
// differ in round-off. A run therefore records the plans its solvers chose (some are made at the
// first step) in <run>/fftw_wisdom/, one file per rank, with every checkpoint; a restart loads them
// before it builds its solver, so it computes with the interrupted run's transforms and continues it
// bit for bit.
#include "app/model.hpp"

namespace ibvalve::app {

/// On a restart: loads this rank's plans from <run>/fftw_wisdom/ when every rank has its file (the same
/// rank count as the run's); call before building the fluid solver. Collective.
void load_fftw_plans(const RunContext& context);
/// Writes each rank's plans chosen so far to <run>/fftw_wisdom/ (with each checkpoint). Collective.
void save_fftw_plans(const RunContext& context);

} // namespace ibvalve::app
