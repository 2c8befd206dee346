#include "hemodynamics/ventricle.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "hemodynamics/report_layout.hpp"
#include "io/files.hpp"

namespace ibvalve::hemodynamics {

namespace {

using Json = nlohmann::ordered_json;

Json entry(const std::string& symbol, const std::string& unit, const std::string& description, double value,
           const std::string& note = "")
{
  Json o{{"value", std::isfinite(value) ? Json(value) : Json()},
         {"unit", unit},
         {"symbol", symbol},
         {"description", description}};
  if (!note.empty()) o["note"] = note;
  return o;
}

/// The rows of the cycle [t0, t1] (the cycle's ends are rows: runs record each cycle's last step).
std::vector<std::size_t> cycle_rows(const std::vector<double>& t, double t0, double t1)
{
  const double slack = 1e-9 * std::max(1.0, std::abs(t1));
  std::vector<std::size_t> rows;
  for (std::size_t i = 0; i < t.size(); ++i)
    if (t[i] >= t0 - slack && t[i] <= t1 + slack) rows.push_back(i);
  if (rows.size() < 2) throw std::invalid_argument("the cycle holds fewer than two rows of V_LV");
  return rows;
}

/// The compartments' columns: the loop's chamber volumes, pressures and flows (lower-case p, so the
/// report's P_LV, P_Ao, ... are not among them) and the sides' P_upstream, P_downstream, Q_upstream,
/// Q_downstream.
bool compartment_column(const std::string& name)
{
  auto starts = [&](const char* prefix) { return name.rfind(prefix, 0) == 0; };
  return starts("V_") || starts("p_") || (starts("Q_") && name != "Q_valve" && name != "Q_outlet") ||
         name == "P_upstream" || name == "P_downstream";
}

void add_periodicity(const io::CsvTable& table, const std::vector<std::size_t>& rows, Json& out)
{
  double worst = 0.0;
  std::string worst_name;
  for (std::size_t c = 0; c < table.columns.size(); ++c) {
    const std::string& name = table.columns[c];
    if (!compartment_column(name) || name == "V_blood") continue;
    double lo = INFINITY, hi = -INFINITY;
    for (std::size_t i : rows) {
      lo = std::min(lo, table.rows[i][c]);
      hi = std::max(hi, table.rows[i][c]);
    }
    const double change = std::abs(table.rows[rows.back()][c] - table.rows[rows.front()][c]);
    const double relative = hi > lo ? change / (hi - lo) : 0.0;
    out["periodicity_" + name] = entry(
        "per_" + name, "1", "|" + name + " at the cycle's end - at its start| / its swing over the cycle",
        relative, fmt::format("changed by {:.4g} over the cycle", change));
    if (relative >= worst) {
      worst = relative;
      worst_name = name;
    }
  }
  out["loop_periodicity"] =
      entry("per_loop", "1", "the largest compartment's periodicity error over the cycle", worst,
            "largest: " + worst_name);
}

} // namespace

bool is_ventricle_metric(const std::string& key)
{
  for (const char* k : {"end_diastolic_volume", "end_systolic_volume", "stroke_volume", "ejection_fraction",
                        "stroke_work", "valve_share_of_stroke_work", "loop_periodicity"})
    if (key == k) return true;
  return key.rfind("periodicity_", 0) == 0;
}

Json ventricle_metrics(const std::filesystem::path& series_file, double t0, double t1,
                       std::optional<double> energy_loss_mJ)
{
  const io::CsvTable table = io::read_csv(series_file);
  if (std::find(table.columns.begin(), table.columns.end(), "V_LV") == table.columns.end())
    return Json::object();
  const bool chamber = std::find(table.columns.begin(), table.columns.end(), "p_LV") != table.columns.end();
  const std::vector<double> t = table.values("t"), volume = table.values("V_LV");
  const std::vector<double> pressure = table.values(chamber ? "p_LV" : "P_LV");
  const std::vector<std::size_t> rows = cycle_rows(t, t0, t1);
  double edv = -INFINITY, esv = INFINITY, area = 0.0;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const std::size_t i = rows[k];
    edv = std::max(edv, volume[i]);
    esv = std::min(esv, volume[i]);
    if (k > 0) area -= 0.5 * (pressure[i] + pressure[rows[k - 1]]) * (volume[i] - volume[rows[k - 1]]);
  }
  // The loop closes when the state is periodic; the change over the cycle is in the periodicity below.
  const double stroke_work = area * mmHg_mL_in_mJ();
  const std::string p = chamber ? "p_LV" : "P_LV";
  Json out = Json::object();
  out["end_diastolic_volume"] = entry("EDV", "mL", "largest LV volume in the cycle", edv);
  out["end_systolic_volume"] = entry("ESV", "mL", "smallest LV volume in the cycle", esv);
  out["stroke_volume"] = entry("SV", "mL", "EDV - ESV", edv - esv);
  out["ejection_fraction"] = entry("EF", "%", "SV / EDV", 100.0 * (edv - esv) / edv);
  out["stroke_work"] = entry(
      "SW", "mJ", "the LV pressure-volume loop's area, -closed integral of " + p + " dV_LV", stroke_work);
  const double share = energy_loss_mJ && stroke_work > 0.0 ? *energy_loss_mJ / stroke_work : NAN;
  out["valve_share_of_stroke_work"] =
      entry("E_L/SW", "%", "the energy lost across the valve as a share of the ventricle's stroke work",
            100.0 * share);
  add_periodicity(table, rows, out);
  return out;
}

void add_ventricle_metrics(Json& doc, const std::filesystem::path& series_file, const ValveMetrics& metrics)
{
  const double energy_loss = metrics.value("energy_loss");
  const Json ventricle =
      ventricle_metrics(series_file, metrics.phases.cycle_start, metrics.phases.cycle_end,
                        std::isfinite(energy_loss) ? std::optional(energy_loss) : std::nullopt);
  for (const auto& [key, m] : ventricle.items()) {
    doc["metrics"][key] = m;
    doc["metrics"][key]["group"] = metric_group(key);
  }
}

} // namespace ibvalve::hemodynamics
