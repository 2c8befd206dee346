#pragma once
// The case-file keys of windkessel/ (io/key_binder.hpp), each section under a prefix the model chooses:
//
//   <prefix>.preset (a named parameter set, or "none") and <prefix>.proximal_resistance,
//     .distal_resistance [mmHg s/mL], .compliance [mL/mmHg], .distal_pressure, .initial_pressure [mmHg],
//     each overriding the preset's value: a three-element Windkessel;
//   <prefix>.file (a CSV table of one period), .time_column, .value_column, .interpolation: a periodic
//     waveform (the LV pressure).
#include <filesystem>
#include <string>

#include "io/key_binder.hpp"
#include "windkessel/waveform.hpp"
#include "windkessel/windkessel.hpp"

namespace ibvalve::windkessel {

struct WindkesselKeys {
  std::string preset;
  WindkesselParameters parameters; // CGS: the preset's, each key given replacing its value
};

/// Declares or reads the Windkessel's keys under `prefix`.
void bind(io::KeyBinder& keys, WindkesselKeys& k, const std::string& prefix);
/// Reading binder: InputError naming the first parameter that neither the case nor a preset gives (for a
/// model that uses the Windkessel: one may bind it and use it in some of its modes only).
void check(const io::KeyBinder& keys, const WindkesselKeys& k);

struct WaveformKeys {
  std::filesystem::path file; // empty when the case gives none (a table that is not required)
  std::string time_column, value_column;
  Interpolation interpolation = Interpolation::monotone_cubic;
};

/// Declares or reads a waveform table's keys under `prefix`; `doc` says what the table holds. The file is
/// required unless `file_required` is false (a model that needs the table only in some of its modes
/// checks the key itself).
void bind(io::KeyBinder& keys, WaveformKeys& k, const std::string& prefix, const std::string& doc,
          bool file_required = true);

/// The waveform the keys name, its values in the table's unit times `value_factor`.
PeriodicWaveform load_waveform(const WaveformKeys& k, double value_factor);

} // namespace ibvalve::windkessel
