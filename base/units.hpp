#pragma once
// CGS inside (cm, g, s; dyn/cm^2); users write mmHg, kPa, mL, ... at the edges. Conversion factors
// turn a value in the named unit into CGS: value_cgs = value * factor.
#include <optional>
#include <string_view>

namespace ibvalve::units {

inline constexpr double mmHg = 1333.22;          // dyn/cm^2 (docs/reference.md, "Units")
inline constexpr double kPa = 1.0e4;             // dyn/cm^2
inline constexpr double Pa = 10.0;               // dyn/cm^2
inline constexpr double mL = 1.0;                // cm^3
inline constexpr double cP = 0.01;               // poise = g/(cm s)
inline constexpr double mm = 0.1;                // cm
inline constexpr double ms = 1.0e-3;             // s
inline constexpr double mJ = 1.0e4;              // erg
inline constexpr double m_per_s = 100.0;         // cm/s
inline constexpr double per_minute = 1.0 / 60.0; // 1/s (a heart rate in beats per minute)

/// The factor that converts a value written in `unit` to CGS, or nothing for an unknown unit.
/// An empty unit (or "1") is dimensionless. Every unit a case file may use is listed here.
std::optional<double> to_cgs(std::string_view unit);

} // namespace ibvalve::units
