#include "base/units.hpp"

#include <array>
#include <utility>

namespace ibvalve::units {

std::optional<double> to_cgs(std::string_view unit)
{
  static constexpr std::array<std::pair<std::string_view, double>, 31> table{{
      {"", 1.0},
      {"1", 1.0},
      {"cm", 1.0},
      {"mm", mm},
      {"m", 100.0},
      {"s", 1.0},
      {"ms", ms},
      {"g", 1.0},
      {"g/mL", 1.0},
      {"g/cm^3", 1.0},
      {"kg/m^3", 1.0e-3},
      {"cP", cP},
      {"P", 1.0},
      {"Pa s", Pa},
      {"dyn/cm^2", 1.0},
      {"Pa", Pa},
      {"kPa", kPa},
      {"mmHg", mmHg},
      {"mL", mL},
      {"cm^3", 1.0},
      {"mL/s", mL},
      {"cm/s", 1.0},
      {"m/s", m_per_s},
      {"mmHg s/mL", mmHg / mL},
      {"mL/mmHg", mL / mmHg},
      {"mmHg/mL", mmHg / mL},     // elastance
      {"mmHg s^2/mL", mmHg / mL}, // inertance
      {"dyn/cm^3", 1.0},
      {"dyn s/cm^3", 1.0},
      {"1/s", 1.0},
      {"1/min", per_minute},
  }};
  for (const auto& [name, factor] : table)
    if (name == unit) return factor;
  return std::nullopt;
}

} // namespace ibvalve::units
