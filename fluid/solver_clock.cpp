#include "fluid/solver_clock.hpp"

#include <array>
#include <stdexcept>
#include <vector>

namespace ibvalve::fluid {

void write_solver_clock(io::Hdf5File& file, const std::string& group, const SolverClock& clock)
{
  const std::array<double, 3> times{clock.time, clock.pressure_time, clock.last_dt};
  const std::array<std::int64_t, 2> counters{clock.steps, clock.have_old_convection ? 1 : 0};
  const std::array<hsize_t, 1> three{3}, two{2};
  file.write_root(group + "/clock", times, three);
  file.write_root(group + "/counters", counters, two);
}

SolverClock read_solver_clock(const io::Hdf5File& file, const std::string& group, const std::string& what)
{
  if (!file.has(group + "/clock") || !file.has(group + "/counters"))
    throw std::runtime_error(file.path().string() + ": " + group + " is not a " + what);
  const std::vector<double> times = file.read(group + "/clock");
  const std::vector<std::int64_t> counters = file.read_integers(group + "/counters");
  if (times.size() != 3 || counters.size() != 2)
    throw std::runtime_error(file.path().string() + ": " + group + " is not a " + what);
  return {times[0], times[1], times[2], counters[0], counters[1] != 0};
}

} // namespace ibvalve::fluid
