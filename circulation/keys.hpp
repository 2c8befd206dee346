#pragma once
// The case-file keys of the closed-loop circulation (io/key_binder.hpp), all under `circulation.`:
// `preset` names a parameter set (circulation/closed_loop.hpp, regazzoni2022()); every parameter has a
// key that overrides the preset's value, in the units the tables of docs/circulation.md use:
//
//   heart_rate [1/min]
//   <chamber>.{active_elastance, passive_elastance} [mmHg/mL], .rest_volume [mL],
//   <chamber>.{contraction_start, contraction_time, relaxation_time} [fraction of the beat]
//     for left_atrium, left_ventricle, right_atrium, right_ventricle;
//   <valve>.{open_resistance, closed_resistance} [mmHg s/mL] for mitral_valve, aortic_valve,
//     tricuspid_valve, pulmonary_valve;  aortic_valve.model = "diode" | "orifice";
//   <compartment>.{resistance [mmHg s/mL], compliance [mL/mmHg], inertance [mmHg s^2/mL]} for
//     systemic_arteries, systemic_veins, pulmonary_arteries, pulmonary_veins.
//
// The valves' switch slope and the initial state are the preset's (docs/circulation.md).
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "circulation/closed_loop.hpp"
#include "io/key_binder.hpp"

namespace ibvalve::circulation {

/// A named parameter set: "regazzoni2022" (docs/circulation.md, "Parameters").
std::optional<CirculationParameters> preset(std::string_view name);
std::vector<std::string> preset_names();

struct CirculationKeys {
  std::string preset;
  CirculationParameters parameters; // CGS; the orifice aortic valve's parameters are the caller's to set
};

/// Declares or reads the keys above (reading: the preset's values, then each key given).
void bind(io::KeyBinder& keys, CirculationKeys& k);
/// What the schema cannot say, as an InputError naming the key (reading binder): each chamber's
/// contraction and relaxation fit in one beat, each valve's closed resistance is above its open one.
void check(const io::KeyBinder& keys, const CirculationKeys& k);

} // namespace ibvalve::circulation
