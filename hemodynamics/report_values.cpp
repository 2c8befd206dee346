#include "hemodynamics/report_values.hpp"

#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "hemodynamics/plotting.hpp"
#include "hemodynamics/report.hpp"
#include "hemodynamics/report_layout.hpp"

namespace ibvalve::hemodynamics {

namespace fs = std::filesystem;
using kainjow::mustache::data;

namespace {

constexpr PlotCaption report_plot_captions[] = {
    {"flow.png",
     "Flow through the valve Q(t), phases shaded: forward ejection, closing regurgitation, leakage"},
    {"pressures.png", "P_LV (driving), P_Ao (outlet) and P_Wk (Windkessel reservoir)"},
    {"pressure_difference.png", "P_nlv - P_nao across the leaflets; its mean over ejection is the TPG"},
    {"orifice_area.png", "Orifice area, opening / fully open / closing shaded"},
    {"pv_loop.png",
     "The LV pressure-volume loop of a run inside the closed-loop circulation: its area is the "
     "stroke work"},
};

double number(const Json& v)
{
  return v.is_number() ? v.get<double>() : NAN;
}

std::string text(const Json& m, const char* field)
{
  const auto f = m.find(field);
  return f != m.end() && f->is_string() ? f->get<std::string>() : std::string();
}

/// One row of the metric tables.
data metric_row(const std::string& key, const Json& m)
{
  const Json& v = m.at("value");
  data row;
  row.set("key", key);
  row.set("description", text(m, "description"));
  row.set("label", text(m, "description").empty() ? key : text(m, "description"));
  row.set("symbol", text(m, "symbol"));
  row.set("value", format_value(number(v)));
  row.set("exact", v.is_number() ? exact_value(v.get<double>()) : std::string("null"));
  row.set("missing", !v.is_number());
  row.set("unit", text(m, "unit"));
  row.set("note", text(m, "note"));
  // "± 0.91" and "time step 0.91, grid 0.3" when the metric carries an uncertainty, else empty; a source
  // common to the cases shows its signed shift, "grid +0.3 (shared)".
  const auto u = m.find("uncertainty");
  // A section over an empty string is still rendered: an absent part is false, not "".
  if (u != m.end() && u->is_number())
    row.set("uncertainty", "± " + format_value(u->get<double>()));
  else
    row.set("uncertainty", data(false));
  std::vector<std::string> sources;
  const Json by_source = m.value("uncertainty_sources", Json::object());
  const Json shared = m.value("uncertainty_shared", Json::object());
  for (const auto& [name, value] : by_source.items()) {
    const auto shift = shared.find(name);
    if (shift != shared.end() && shift->is_number())
      sources.push_back(fmt::format("{} {}{} (shared)", name, shift->get<double>() > 0.0 ? "+" : "",
                                    format_value(shift->get<double>())));
    else
      sources.push_back(name + " " + format_value(number(value)));
  }
  if (sources.empty())
    row.set("uncertainty_sources", data(false));
  else
    row.set("uncertainty_sources", fmt::format("{}", fmt::join(sources, ", ")));
  return row;
}

/// `metrics` (every metric, in metrics.json's order) and `groups` (the same, grouped: group, metrics).
void set_metric_tables(const Json& doc, data& values)
{
  data all{data::type::list};
  for (const auto& [key, m] : doc.at("metrics").items()) all.push_back(metric_row(key, m));
  values.set("metrics", all);
  data groups{data::type::list};
  for (const char* group : metric_groups()) {
    data rows{data::type::list};
    for (const auto& [key, m] : doc.at("metrics").items())
      if (metric_group(key) == group) rows.push_back(metric_row(key, m));
    if (rows.list_value().empty()) continue;
    data g;
    g.set("group", group);
    g.set("metrics", rows);
    groups.push_back(g);
  }
  values.set("groups", groups);
}

/// `headline`, `checks` and `references`: what the report opens with.
void set_headline(const Json& doc, data& values)
{
  data rows{data::type::list};
  for (const Json& h : doc.value("headline", Json::array())) {
    data row;
    for (const char* field : {"key", "name", "symbol", "unit", "range", "source"})
      row.set(field, text(h, field));
    row.set("value", format_value(number(h.at("value"))));
    row.set("missing", !h.at("value").is_number());
    row.set("outside", text(h, "assessment") == "outside");
    row.set("assessment", text(h, "assessment"));
    rows.push_back(row);
  }
  values.set("headline", rows);
  data checks{data::type::list};
  for (const Json& c : doc.value("checks", Json::array())) {
    data row;
    row.set("check", text(c, "check"));
    row.set("text", text(c, "text"));
    checks.push_back(row);
  }
  values.set("checks", checks);
  // The run's warnings, as its run.json keeps them (app/run_command.cpp).
  data warnings{data::type::list};
  const Json run = doc.value("provenance", Json::object()).value("run", Json::object());
  for (const Json& w : run.value("warnings", Json::array())) {
    data row;
    row.set("text", w.is_string() ? w.get<std::string>() : w.dump());
    warnings.push_back(row);
  }
  values.set("has_warnings", !warnings.list_value().empty());
  values.set("warnings", warnings);
  data references{data::type::list};
  for (const ReferenceSource& s : reference_sources()) {
    data row;
    row.set("name", s.name);
    row.set("citation", s.citation);
    references.push_back(row);
  }
  values.set("references", references);
}

/// `cycle_rows` and `periodicity`: the cycle-to-cycle table (shown from two cycles on).
void set_cycle_table(const Json& doc, const std::string& report_root, data& values)
{
  const Json cycles = doc.value("cycles", Json::array());
  data rows{data::type::list};
  const int reported = doc.value("cycle", Json::object()).value("number", 0);
  if (cycles.size() >= 2)
    for (const Json& c : cycles) {
      data row;
      const int cycle = c.at("cycle").get<int>();
      row.set("cycle", fmt::format("{}", cycle));
      row.set("page", fmt::format("{}cycle_{}/report.html", report_root, cycle));
      row.set("reported", cycle == reported);
      row.set("vf", format_value(number(c.at("forward_volume"))));
      row.set("tpg", format_value(number(c.at("transvalvular_pressure_gradient"))));
      const double start = number(c.at("windkessel_pressure_start")),
                   end = number(c.at("windkessel_pressure_end"));
      row.set("pwk_start", format_value(start));
      row.set("pwk_end", format_value(end));
      row.set("pwk_change", std::isfinite(end - start) ? fmt::format("{:+.3g}", end - start) : "missing");
      rows.push_back(row);
    }
  values.set("has_cycle_table", !rows.list_value().empty());
  values.set("cycle_rows", rows);
  values.set("periodicity", doc.value("periodicity", std::string()));
}

/// `phases` and `ejection_windows`.
void set_phases(const Json& doc, data& values)
{
  data phase_rows{data::type::list};
  for (const auto& [key, v] : doc.at("phases").items()) {
    data row;
    row.set("name", key);
    row.set("time", v.is_string() ? v.get<std::string>() : format_value(number(v)));
    phase_rows.push_back(row);
  }
  values.set("phases", phase_rows);
  data window_rows{data::type::list};
  for (const Json& e : doc.value("ejection_windows", Json::array())) {
    data row;
    row.set("condition", e.at("condition").get<std::string>());
    row.set("start", format_value(number(e.at("start"))));
    row.set("chosen", e.at("chosen").get<bool>());
    row.set("tpg", format_value(number(e.at("transvalvular_pressure_gradient"))));
    row.set("qrms", format_value(number(e.at("rms_forward_flow"))));
    row.set("eoa", format_value(number(e.at("effective_orifice_area"))));
    window_rows.push_back(row);
  }
  values.set("ejection_windows", window_rows);
}

/// `provenance` and `inputs`.
void set_provenance(const Json& doc, data& values)
{
  const Json& provenance = doc.at("provenance");
  data provenance_rows{data::type::list};
  auto provenance_row = [&](const std::string& name, const std::string& value) {
    data row;
    row.set("name", name);
    row.set("value", value);
    provenance_rows.push_back(row);
  };
  auto field = [](const Json& j, const char* key) {
    const auto f = j.find(key);
    return f == j.end() ? std::string("unknown") : f->is_string() ? f->get<std::string>() : f->dump();
  };
  if (const auto run = provenance.find("run"); run != provenance.end()) {
    provenance_row("case file", field(*run, "case_file"));
    provenance_row("run by",
                   fmt::format("ibvalve {} (commit {})", field(*run, "ibvalve"), field(*run, "commit")));
    provenance_row("started", fmt::format("{} on {} rank(s)", field(*run, "started"), field(*run, "ranks")));
    for (const auto& restart : run->value("restarts", Json::array()))
      provenance_row("restarted", fmt::format("{} by ibvalve {} (commit {}) on {} rank(s)",
                                              field(restart, "at"), field(restart, "ibvalve"),
                                              field(restart, "commit"), field(restart, "ranks")));
  } else {
    provenance_row("run", "no run.json in the run folder: where it came from is not recorded");
  }
  const Json& report = provenance.at("report");
  provenance_row("report by", fmt::format("ibvalve {} (commit {}) at {}", field(report, "ibvalve"),
                                          field(report, "commit"), field(report, "written")));
  values.set("provenance", provenance_rows);
  data input_rows{data::type::list};
  for (const auto& [key, value] : provenance.at("inputs").items()) {
    data row;
    row.set("key", key);
    row.set("value", value.get<std::string>());
    input_rows.push_back(row);
  }
  values.set("inputs", input_rows);
}

} // namespace

std::span<const PlotCaption> report_plots()
{
  return report_plot_captions;
}

data report_template_values(const Json& doc, const std::vector<fs::path>& plots,
                            const std::string& report_root)
{
  data values;
  values.set("run", doc.at("run").get<std::string>());
  const Json cycle = doc.value("cycle", Json::object());
  values.set("cycle", fmt::format("{}", cycle.value("number", 0)));
  values.set("cycles", fmt::format("{}", cycle.value("of", 0)));
  const Json& phases = doc.at("phases");
  values.set("cycle_start", format_value(number(phases.at("cycle_start"))));
  values.set("cycle_end", format_value(number(phases.at("cycle_end"))));
  set_headline(doc, values);
  set_metric_tables(doc, values);
  set_cycle_table(doc, report_root, values);
  set_phases(doc, values);
  values.set("plots", plot_template_rows(plots, report_plot_captions));
  data notes{data::type::list};
  for (const auto& n : doc.at("notes")) {
    data row;
    row.set("text", n.get<std::string>());
    notes.push_back(row);
  }
  values.set("notes", notes);
  set_provenance(doc, values);
  return values;
}

} // namespace ibvalve::hemodynamics
