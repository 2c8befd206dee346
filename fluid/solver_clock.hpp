#pragma once
// The clock of a time-stepping fluid solver as a checkpoint holds it (docs/runs.md): what the next step
// needs besides the fields, shared by NavierStokes and NestedNavierStokes.
#include <cstdint>
#include <string>

#include "io/hdf5.hpp"

namespace ibvalve::fluid {

struct SolverClock {
  double time = 0.0;          // t^n of the velocity
  double pressure_time = 0.0; // t^{n-1/2} of the pressure
  double last_dt = 0.0;       // the step the Adams-Bashforth extrapolation scales by
  std::int64_t steps = 0;
  bool have_old_convection = false; // N^n exists (false: the next step starts with Heun)
};

/// `group`/clock (time, pressure time, last dt) and `group`/counters (steps, have_old_convection); rank 0
/// writes. Collective.
void write_solver_clock(io::Hdf5File& file, const std::string& group, const SolverClock& clock);
/// Reads what write_solver_clock wrote; std::runtime_error naming the file and group when it is not there
/// or not of that shape (`what` names the solver in the message, e.g. "fluid checkpoint").
SolverClock read_solver_clock(const io::Hdf5File& file, const std::string& group, const std::string& what);

} // namespace ibvalve::fluid
