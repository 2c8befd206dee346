#include "hemodynamics/cycle_table.hpp"

#include <cmath>
#include <optional>

#include <fmt/format.h>

namespace ibvalve::hemodynamics {

using Json = nlohmann::ordered_json;

namespace {

Json number_or_null(double v)
{
  return std::isfinite(v) ? Json(v) : Json();
}

std::optional<double> number(const Json& row, const char* key)
{
  const auto v = row.find(key);
  return v != row.end() && v->is_number() ? std::optional(v->get<double>()) : std::nullopt;
}

} // namespace

Json cycle_table(const ValveSeries& series, const MetricSettings& settings, int last)
{
  Json rows = Json::array();
  MetricSettings one = settings;
  for (int cycle = 1; cycle <= last; ++cycle) {
    one.cycle = cycle;
    const ValveMetrics m = compute_metrics(series, one);
    rows.push_back(
        Json{{"cycle", cycle},
             {"forward_volume", number_or_null(m.value("forward_volume"))},
             {"transvalvular_pressure_gradient", number_or_null(m.value("transvalvular_pressure_gradient"))},
             {"windkessel_pressure_start", number_or_null(m.value("windkessel_pressure_start"))},
             {"windkessel_pressure_end", number_or_null(m.value("windkessel_pressure_end"))}});
  }
  return rows;
}

std::string periodicity_summary(const Json& cycles)
{
  if (cycles.size() < 2) return {};
  const Json& now = cycles.back();
  const Json& before = cycles[cycles.size() - 2];
  const int cycle = now.at("cycle").get<int>();
  auto change = [&](const char* key, const char* symbol) {
    const auto a = number(before, key), b = number(now, key);
    if (!a || !b || *a == 0.0) return fmt::format("{} cannot be compared", symbol);
    return fmt::format("{} by {:+.2g} %", symbol, 100.0 * (*b - *a) / std::abs(*a));
  };
  std::string text =
      fmt::format("Cycle {} against cycle {}: {}, {}", cycle, cycle - 1, change("forward_volume", "V_F"),
                  change("transvalvular_pressure_gradient", "TPG"));
  const auto start = number(now, "windkessel_pressure_start"), end = number(now, "windkessel_pressure_end");
  if (start && end) {
    const double drift = *end - *start;
    text += fmt::format("; P_Wk changes by {:+.3g} mmHg over the cycle: {} (tolerance {:g} mmHg)", drift,
                        std::abs(drift) > periodic_pressure_tolerance ? "not periodic" : "periodic",
                        periodic_pressure_tolerance);
  }
  return text;
}

} // namespace ibvalve::hemodynamics
