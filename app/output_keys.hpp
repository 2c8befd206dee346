#pragma once
// The time loop's output keys (app/time_loop.hpp): one vocabulary, the same meaning in every model that
// has the key (docs/runs.md, "Outputs"):
//
//   output.every            a row of timeseries.csv every this many steps (and at the first and the last);
//   output.fields_interval  simulated time between field snapshots, s (fields/*.h5 with the XDMF series;
//                           and the first and the last snapshot); 0 = none.
//
// The spellings of older versions (output.timeseries_every, output.fields_every, and an ibfe case's
// output.every, which counted field snapshots there) are refused with the key to write instead.
#include <cstdint>
#include <optional>

#include "io/key_binder.hpp"

namespace ibvalve::app {

/// output.every bound to `every`, defaulting to `default_every` steps.
void bind_row_every(io::KeyBinder& keys, std::int64_t& every, std::int64_t default_every);

/// output.fields_interval bound to `interval`, defaulting to `default_interval` (s); without one, a case
/// that does not give the key has the first and the last snapshot alone. `series` names the XDMF series
/// the model writes, for the key's meaning.
void bind_fields_interval(io::KeyBinder& keys, std::optional<double>& interval,
                          std::optional<double> default_interval, const char* series);

/// Refuses output.every where it once counted field snapshots (an ibfe case), naming
/// output.fields_interval; such a model writes a row every step.
void retire_every_as_fields(io::KeyBinder& keys);

/// Refuses the retired spellings every case may hold (app/model.hpp, common_schema): each names its key.
void retire_output_spellings(io::Schema& schema);

/// TimeLoop::fields_every of an output.fields_interval at a fixed `step`: the nearest whole number of
/// steps (at least 1); 0 (the first and last snapshot alone) when unset; -1 (none) for 0.
std::int64_t fields_every_steps(const std::optional<double>& interval, double step);

} // namespace ibvalve::app
