#include "app/output_keys.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace ibvalve::app {

namespace {
constexpr const char* every_key = "output.every";
constexpr const char* interval_key = "output.fields_interval";
} // namespace

void bind_row_every(io::KeyBinder& keys, std::int64_t& every, std::int64_t default_every)
{
  keys.integer(every_key, "write a time-series row every this many steps", every)
      .defaults(default_every)
      .at_least(1);
}

void bind_fields_interval(io::KeyBinder& keys, std::optional<double>& interval,
                          std::optional<double> default_interval, const char* series)
{
  std::string doc = std::string("simulated time between field snapshots (fields/*.h5 with ") + series +
                    " for ParaView); 0 = none";
  if (!default_interval) doc += "; unset = the first and the last alone";
  io::KeyBuilder key = keys.real(interval_key, doc, interval);
  key.unit("s").non_negative();
  if (default_interval) key.defaults(*default_interval);
}

void retire_every_as_fields(io::KeyBinder& keys)
{
  keys.retired(every_key, std::string("counted the field snapshots' steps in this model: write ") +
                              interval_key +
                              ", the simulated time between them in s (N steps = N x time.step); its "
                              "time-series rows are every step");
}

void retire_output_spellings(io::Schema& schema)
{
  schema.retire("output.timeseries_every",
                std::string("renamed ") + every_key + " (a time-series row every this many steps)");
  schema.retire("output.fields_every",
                std::string("replaced by ") + interval_key +
                    ", the simulated time between field snapshots in s (N steps = N x time.step)");
}

std::int64_t fields_every_steps(const std::optional<double>& interval, double step)
{
  if (!interval) return 0;
  if (*interval <= 0.0) return -1;
  return std::max<std::int64_t>(1, std::llround(*interval / step));
}

} // namespace ibvalve::app
