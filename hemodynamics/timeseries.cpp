#include "hemodynamics/timeseries.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <stdexcept>

#include "base/errors.hpp"
#include "io/files.hpp"

namespace ibvalve::hemodynamics {

std::vector<std::string> standard_columns()
{
  return {column::time,
          column::valve_flow,
          column::outlet_flow,
          column::lv_pressure,
          column::aortic_pressure,
          column::windkessel_pressure,
          column::near_lv_pressure,
          column::near_aortic_pressure,
          column::orifice_area};
}

std::vector<std::string> standard_units()
{
  return {"s", "mL/s", "mL/s", "mmHg", "mmHg", "mmHg", "mmHg", "mmHg", "cm^2"};
}

std::vector<std::string> leaflet_state_columns()
{
  return {column::displacement_mean,  column::displacement_max, column::peak_velocity,
          column::belly_fiber_strain, column::top_fiber_strain, column::belly_fiber_stress,
          column::top_fiber_stress};
}

std::vector<std::string> leaflet_state_units()
{
  return {"cm", "cm", "cm/s", "1", "1", "kPa", "kPa"};
}

std::vector<std::vector<double>*> ValveSeries::columns()
{
  std::vector<std::vector<double>*> all{&t,
                                        &valve_flow,
                                        &outlet_flow,
                                        &lv_pressure,
                                        &aortic_pressure,
                                        &windkessel_pressure,
                                        &near_lv_pressure,
                                        &near_aortic_pressure,
                                        &orifice_area};
  for (auto& [name, values] : leaflet_state) all.push_back(&values);
  std::erase_if(all, [](const std::vector<double>* c) { return c->empty(); });
  return all;
}

std::vector<const std::vector<double>*> ValveSeries::columns() const
{
  std::vector<const std::vector<double>*> out;
  for (auto* c : const_cast<ValveSeries*>(this)->columns()) out.push_back(c);
  return out;
}

ValveSeries read_valve_series(const std::filesystem::path& file)
{
  const io::CsvTable table = io::read_csv(file);
  ValveSeries s;
  s.source = file;
  s.t = table.values(column::time);
  s.valve_flow = table.values(column::valve_flow);
  s.lv_pressure = table.values(column::lv_pressure);
  s.aortic_pressure = table.values(column::aortic_pressure);
  s.near_lv_pressure = table.values(column::near_lv_pressure);
  s.near_aortic_pressure = table.values(column::near_aortic_pressure);
  auto optional = [&](const char* name, std::vector<double>& into) {
    if (std::find(table.columns.begin(), table.columns.end(), name) != table.columns.end())
      into = table.values(name);
  };
  optional(column::outlet_flow, s.outlet_flow);
  optional(column::windkessel_pressure, s.windkessel_pressure);
  optional(column::orifice_area, s.orifice_area);
  for (const std::string& name : leaflet_state_columns())
    if (std::find(table.columns.begin(), table.columns.end(), name) != table.columns.end())
      s.leaflet_state[name] = table.values(name);
  if (s.t.size() < 3) throw InputError(file.string() + ": needs at least 3 rows of samples");
  // Data rows start after the header; comment lines make exact line numbers unknowable here, so the
  // row number (1 = first data row) is given.
  for (const auto* c : s.columns())
    for (std::size_t i = 0; i < c->size(); ++i)
      if (!std::isfinite((*c)[i]))
        throw InputError(fmt::format("{}: data row {}: a value is not finite", file.string(), i + 1));
  for (std::size_t i = 1; i < s.t.size(); ++i)
    if (!(s.t[i] > s.t[i - 1]))
      throw InputError(
          fmt::format("{}: data row {}: time {} does not increase", file.string(), i + 1, s.t[i]));
  return s;
}

double interpolate(const std::vector<double>& t, const std::vector<double>& y, double x)
{
  if (x <= t.front()) return y.front();
  if (x >= t.back()) return y.back();
  const auto k = static_cast<std::size_t>(std::upper_bound(t.begin(), t.end(), x) - t.begin()) - 1;
  const double s = (x - t[k]) / (t[k + 1] - t[k]);
  return y[k] + s * (y[k + 1] - y[k]);
}

double integrate(const std::vector<double>& t, const std::vector<double>& y, double a, double b)
{
  if (b < a) return -integrate(t, y, b, a);
  a = std::max(a, t.front());
  b = std::min(b, t.back());
  if (b <= a) return 0.0;
  // Trapezoids between consecutive knots of {a, samples inside (a, b), b}.
  auto first = std::upper_bound(t.begin(), t.end(), a);
  const auto last = std::lower_bound(t.begin(), t.end(), b);
  double previous_t = a, previous_y = interpolate(t, y, a), sum = 0.0;
  for (auto it = first; it != last; ++it) {
    const std::size_t i = static_cast<std::size_t>(it - t.begin());
    sum += 0.5 * (t[i] - previous_t) * (y[i] + previous_y);
    previous_t = t[i];
    previous_y = y[i];
  }
  sum += 0.5 * (b - previous_t) * (interpolate(t, y, b) + previous_y);
  return sum;
}

ValveSeries time_window(const ValveSeries& series, double start, double end)
{
  const double slack = 1e-9 * std::max(1.0, std::abs(end));
  if (!(start < end) || start < series.t.front() - slack || end > series.t.back() + slack)
    throw std::invalid_argument(fmt::format("time window [{}, {}] s is not inside the series [{}, {}] s",
                                            start, end, series.t.front(), series.t.back()));
  ValveSeries out = series;
  const auto in = series.columns();
  auto into = out.columns();
  for (auto* c : into) c->clear();
  const double tiny = 1e-12 * (series.t.back() - series.t.front());
  auto push = [&](double x, std::size_t i, bool exact) {
    for (std::size_t c = 0; c < in.size(); ++c)
      into[c]->push_back(exact ? (*in[c])[i] : (c == 0 ? x : interpolate(series.t, *in[c], x)));
  };
  push(start, 0, false);
  for (std::size_t i = 0; i < series.t.size(); ++i)
    if (series.t[i] > start + tiny && series.t[i] < end - tiny) push(0.0, i, true);
  push(end, 0, false);
  return out;
}

} // namespace ibvalve::hemodynamics
