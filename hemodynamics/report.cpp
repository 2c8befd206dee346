#include "hemodynamics/report.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "base/build_info.hpp"
#include "base/errors.hpp"
#include "base/logger.hpp"
#include "hemodynamics/cycle_table.hpp"
#include "hemodynamics/plotting.hpp"
#include "hemodynamics/report_layout.hpp"
#include "hemodynamics/report_values.hpp"
#include "hemodynamics/text_template.hpp"
#include "hemodynamics/ventricle.hpp"
#include "io/files.hpp"
#include "io/recorded_config.hpp"

namespace ibvalve::hemodynamics {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// Settings

void bind_report(io::KeyBinder& keys, ReportSettings& r, const std::string& prefix)
{
  const std::string p = prefix + ".";
  MetricSettings& m = r.metrics;
  keys.real(p + "period", "cardiac cycle of the metrics (must match the driving waveform)", m.period)
      .unit("s")
      .defaults(0.8)
      .positive();
  keys.integer(p + "cycle",
               "the reported cycle, counted from 1 (1 = the first; -1 = the last whole cycle): report/ holds "
               "its report, report/cycle_N/ each cycle's",
               m.cycle)
      .defaults(std::int64_t{-1})
      .at_least(-1);
  keys.real(p + "forward_threshold", "forward ejection is valve flow above this", m.forward_threshold)
      .unit("mL/s")
      .defaults(0.0);
  std::vector<std::pair<std::string, ClosureRule>> rules;
  for (const ClosureRule rule : {ClosureRule::flow, ClosureRule::area, ClosureRule::automatic})
    rules.emplace_back(closure_rule_name(rule), rule);
  keys.choice(p + "closure_rule", "how the closure instant is found (docs/hemodynamics.md)", m.closure_rule,
              rules)
      .defaults(std::string("flow"));
  keys.real(p + "closure_flow_fraction",
            "rule 'flow': closed once Q is back to this fraction of the peak backflow",
            m.closure_flow_fraction)
      .defaults(0.1)
      .above(0.0)
      .below(1.0);
  keys.real(p + "open_area_fraction", "normalised orifice area counted as fully open", m.open_area_fraction)
      .defaults(0.9)
      .above(0.0)
      .below(1.0);
  keys.real(p + "closed_area_fraction", "normalised orifice area counted as closed", m.closed_area_fraction)
      .defaults(0.05)
      .above(0.0)
      .below(1.0);
  keys.boolean(p + "plots", "draw the report's plots (matplotlib)", r.plots).defaults(true);
  keys.boolean(p + "cycle_plots",
               "draw the plots on every cycle's own page (report/cycle_N/) too; false: on the reported "
               "cycle's only (a run of many settling cycles: about half a second a page)",
               r.cycle_plots)
      .defaults(true);
  keys.path(p + "templates",
            "folder of report.html.tpl and/or report.md.tpl laid out in place of the built-in ones (`ibvalve "
            "report --write-templates DIR` copies those)",
            r.templates, false);
  if (keys.reading() && m.cycle == 0)
    keys.fail(m.cycle, "cycles count from 1 (1 = the first, -1 = the last whole cycle)");
  if (keys.reading() && m.closed_area_fraction >= m.open_area_fraction)
    keys.fail(m.closed_area_fraction, "must be below " + keys.key_of(m.open_area_fraction));
}

void check_report_templates(const io::KeyBinder& keys, const ReportSettings& r)
{
  if (r.templates.empty()) return;
  if (!fs::is_directory(r.templates)) keys.fail(r.templates, "no such folder '" + r.templates.string() + "'");
  // A template that does not parse is refused now, not after the run.
  load_page_templates("report", r.templates, "report.templates");
}

RecordedReport recorded_report(const fs::path& run_directory)
{
  RecordedReport recorded;
  const fs::path file = run_directory / "config.toml";
  if (!fs::exists(file)) return recorded;
  toml::table root = io::parse_toml_file(file);
  // The EOA's density is the fluid's the run simulated, one density for the run and its report. Run
  // folders of older builds recorded a report.density of its own: passed over.
  const toml::node* fluid_density = root.at_path("fluid.density").node();
  const bool period_given = root.at_path("report.period").node() != nullptr;
  if (toml::table* report = root["report"].as_table()) {
    report->erase("density");
    // The [report] table alone (moved, so that messages keep its lines), checked by the [report] schema.
    toml::table table;
    table.insert("report", std::move(*report));
    io::Schema schema;
    {
      io::KeyBinder declaring(schema);
      ReportSettings unused;
      bind_report(declaring, unused);
    }
    const io::Config config = io::Config::validate(std::move(table), file, schema);
    io::KeyBinder keys(config);
    bind_report(keys, recorded.report);
    if (period_given) recorded.period = recorded.report.metrics.period;
  }
  if (fluid_density && fluid_density->is_number())
    recorded.report.metrics.density = *fluid_density->value<double>();
  return recorded;
}

MetricSettings metric_settings_from_run(const fs::path& run_directory)
{
  return recorded_report(run_directory).report.metrics;
}

// ---------------------------------------------------------------------------------------------
// Formatting helpers

std::string metrics_summary(const fs::path& metrics_json)
{
  const Json doc = Json::parse(io::read_text_file(metrics_json));
  const Json& m = doc.at("metrics");
  std::string line;
  auto add = [&](const char* key, const char* symbol, bool always) {
    if (!m.contains(key) && !always) return;
    std::string shown = "missing";
    if (m.contains(key)) {
      const Json& entry = m.at(key);
      const Json& v = entry.at("value");
      shown = (v.is_number() ? format_value(v.get<double>()) : std::string("missing")) + " " +
              entry.at("unit").get<std::string>();
    }
    line += (line.empty() ? "" : ", ") + std::string(symbol) + " " + shown;
  };
  add("forward_volume", "V_F", true);
  add("regurgitant_fraction", "RF", true);
  add("transvalvular_pressure_gradient", "TPG", true);
  add("effective_orifice_area", "EOA", true);
  add("energy_loss", "E_L", true);
  add("peak_velocity_open", "u_max,FO", false);
  return line;
}

std::string format_value(double value)
{
  if (!std::isfinite(value)) return "missing";
  return fmt::format("{:.4g}", value);
}

std::string exact_value(double value)
{
  if (!std::isfinite(value)) return "null";
  char buffer[64];
  const auto [end, error] = std::to_chars(buffer, buffer + sizeof buffer, value);
  (void)error; // 64 characters hold every double
  return std::string(buffer, end);
}

std::string csv_field(const std::string& text)
{
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char ch : text) out += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return out + "\"";
}

// ---------------------------------------------------------------------------------------------
// metrics.json

namespace {

Json metric_json(const std::string& symbol, const std::string& unit, const std::string& description,
                 std::optional<double> value, const std::string& note)
{
  Json o{{"value", value ? Json(*value) : Json()},
         {"unit", unit},
         {"symbol", symbol},
         {"description", description}};
  if (!note.empty()) o["note"] = note;
  return o;
}

/// The case's tables that are not its physics: where and how it writes, logs and reports.
bool is_input_key(const std::string& key)
{
  for (const char* table : {"output.", "log.", "petsc.", "run.", "report.", "checkpoint."})
    if (key.rfind(table, 0) == 0) return false;
  return true;
}

} // namespace

Json provenance_document(const fs::path& run_directory)
{
  Json out = Json::object();
  const fs::path record = run_directory / "run.json";
  if (fs::exists(record)) {
    try {
      out["run"] = Json::parse(io::read_text_file(record));
    } catch (const Json::exception& error) {
      throw InputError(record.string() + ": " + error.what());
    }
  }
  out["report"] =
      Json{{"ibvalve", base::version()}, {"commit", base::commit()}, {"written", base::utc_now()}};
  Json inputs = Json::object();
  if (const fs::path config = run_directory / "config.toml"; fs::exists(config))
    for (const io::RecordedEntry& entry : io::read_recorded_config(config))
      if (is_input_key(entry.key))
        inputs[entry.key] = entry.unit.empty() ? entry.value : entry.value + " " + entry.unit;
  out["inputs"] = inputs;
  return out;
}

namespace {

/// A run folder's JSON file of metrics (extra_metrics.json, uncertainty.json): an object, or an
/// InputError naming the file.
Json read_metrics_object(const fs::path& file)
{
  Json doc;
  try {
    doc = Json::parse(io::read_text_file(file));
  } catch (const Json::exception& error) {
    throw InputError(file.string() + ": " + error.what());
  }
  if (!doc.is_object()) throw InputError(file.string() + ": expected a JSON object of metrics");
  return doc;
}

/// Merges a run folder's uncertainty.json ({key: {"uncertainty": u, "sources": {name: u_s}, "shared":
/// {name: signed shift}}}, written by `ibvalve study` from its [[uncertainty]] variants; "shared" only for
/// the sources common to the cases) into the metrics it names: each gets "uncertainty",
/// "uncertainty_sources" and, with shared sources, "uncertainty_shared". Keys without such a metric are
/// ignored; a u that is not a number >= 0, or a shift that is not a finite number of one of the key's
/// sources, is an InputError naming the file and the key.
void add_uncertainties(const fs::path& file, Json& values, Json& notes)
{
  if (!fs::exists(file)) return;
  const Json doc = read_metrics_object(file);
  auto standard = [&](const Json& v, const std::string& what) {
    if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < 0.0)
      throw InputError(fmt::format("{}: {}: expected a number >= 0, not {}", file.string(), what, v.dump()));
    return v.get<double>();
  };
  std::set<std::string> sources;
  for (const auto& [key, entry] : doc.items()) {
    if (!entry.is_object() || !entry.contains("uncertainty"))
      throw InputError(file.string() + ": " + key + ": expected an object with \"uncertainty\"");
    const double u = standard(entry.at("uncertainty"), key + ".uncertainty");
    Json by_source = Json::object();
    const Json given = entry.value("sources", Json::object());
    for (const auto& [name, value] : given.items()) {
      by_source[name] = standard(value, key + ".sources." + name);
      sources.insert(name);
    }
    Json shared = Json::object();
    const Json shifts = entry.value("shared", Json::object());
    for (const auto& [name, value] : shifts.items()) {
      if (!value.is_number() || !std::isfinite(value.get<double>()) || !by_source.contains(name))
        throw InputError(
            fmt::format("{}: {}.shared.{}: expected the finite signed shift of one of its sources, "
                        "not {}",
                        file.string(), key, name, value.dump()));
      shared[name] = value.get<double>();
    }
    if (!values.contains(key)) continue;
    values[key]["uncertainty"] = u;
    values[key]["uncertainty_sources"] = by_source;
    if (!shared.empty()) values[key]["uncertainty_shared"] = shared;
  }
  notes.push_back(fmt::format("standard uncertainties from uncertainty.json (sources: {}): value ± u",
                              fmt::join(sources, ", ")));
}

} // namespace

Json metrics_document(const ValveMetrics& metrics, const MetricSettings& settings,
                      const std::string& run_name, const fs::path& run_directory)
{
  const Json settings_json{{"period_s", settings.period},
                           {"cycle", settings.cycle},
                           {"forward_threshold_mL_per_s", settings.forward_threshold},
                           {"closure_rule", closure_rule_name(settings.closure_rule)},
                           {"closure_flow_fraction", settings.closure_flow_fraction},
                           {"open_area_fraction", settings.open_area_fraction},
                           {"closed_area_fraction", settings.closed_area_fraction},
                           {"density_g_per_mL", settings.density}};
  const Phases& p = metrics.phases;
  const Json phases{{"cycle_start", p.cycle_start},
                    {"cycle_end", p.cycle_end},
                    {"forward_flow_start", p.forward_flow_start},
                    {"pressure_crossover", p.pressure_crossover},
                    {"ejection_start", p.ejection_start},
                    {"ejection_start_condition", p.ejection_start_condition},
                    {"ejection_end", p.ejection_end},
                    {"closure", p.closure},
                    {"closure_rule", p.closure_rule},
                    {"peak_forward_time", p.peak_forward_time},
                    {"peak_regurgitant_time", p.peak_regurgitant_time},
                    {"opening_start", p.opening_start},
                    {"fully_open_start", p.fully_open_start},
                    {"fully_open_end", p.fully_open_end},
                    {"closing_end", p.closing_end}};
  Json values = Json::object();
  for (const Metric& m : metrics.metrics)
    values[m.key] = metric_json(m.symbol, m.unit, m.description, m.value, m.note);
  Json windows = Json::array();
  for (const EjectionWindow& e : metrics.ejection_windows)
    windows.push_back(Json{{"condition", e.condition},
                           {"start", e.start},
                           {"chosen", e.condition == p.ejection_start_condition},
                           {"transvalvular_pressure_gradient", e.transvalvular_pressure_gradient},
                           {"rms_forward_flow", e.rms_forward_flow},
                           {"effective_orifice_area",
                            e.effective_orifice_area ? Json(*e.effective_orifice_area) : Json(nullptr)}});
  Json notes = Json::array();
  for (const auto& n : metrics.notes) notes.push_back(n);
  const fs::path extra_file = run_directory / "extra_metrics.json";
  if (fs::exists(extra_file)) {
    const Json extra = read_metrics_object(extra_file);
    for (const auto& [key, v] : extra.items()) {
      auto text = [&](const char* field) {
        const auto f = v.find(field);
        return f != v.end() && f->is_string() ? f->get<std::string>() : std::string();
      };
      if (v.is_number()) {
        values[key] = metric_json(key, "", "from extra_metrics.json", v.get<double>(), "");
      } else if (v.is_object()) {
        const auto value = v.find("value");
        values[key] = metric_json(
            text("symbol").empty() ? key : text("symbol"), text("unit"), text("description"),
            value != v.end() && value->is_number() ? std::optional(value->get<double>()) : std::nullopt,
            text("note"));
        // A figure measured against generated data says so wherever it is shown (the fit error).
        if (const auto synthetic = v.find("synthetic_data"); synthetic != v.end() && synthetic->is_boolean())
          values[key]["synthetic_data"] = synthetic->get<bool>();
      } else {
        throw InputError(extra_file.string() + ": " + key +
                         ": expected a number or an object with \"value\"");
      }
    }
    notes.push_back("metrics added from extra_metrics.json");
  }
  add_uncertainties(run_directory / "uncertainty.json", values, notes);
  for (auto& [key, m] : values.items()) m["group"] = metric_group(key);
  Json headline = headline_document(values), checks = plausibility_checks(values);
  return Json{{"ibvalve_metrics", 1},
              {"run", run_name},
              {"source", "timeseries.csv"},
              {"cycle", {{"number", metrics.cycle}, {"of", metrics.cycles}}},
              {"settings", settings_json},
              {"headline", std::move(headline)},
              {"checks", std::move(checks)},
              {"phases", phases},
              {"ejection_windows", windows},
              {"metrics", values},
              {"notes", notes},
              {"provenance", provenance_document(run_directory)}};
}

namespace {

/// A period must fit the series: no longer than it, and holding enough rows for phases and integrals.
void check_period(const ValveSeries& series, const fs::path& series_file, const ReportOptions& options)
{
  const double period = options.settings.period;
  const std::string period_name =
      options.period_given ? "command line: --period " + format_value(period)
                           : series_file.string() + ": report.period " + format_value(period) + " s";
  if (series.t.size() < 2) return;
  const double span = series.t.back() - series.t.front();
  const double interval = span / static_cast<double>(series.t.size() - 1);
  if (period > span * (1.0 + 1e-9))
    throw InputError(fmt::format("{}: longer than the series ({} s of {} rows)", period_name,
                                 format_value(span), series.t.size()));
  constexpr double minimum_rows = 10;
  if (period < minimum_rows * interval)
    throw InputError(fmt::format(
        "{}: holds about {} rows of the series (one every {} s); a cycle needs at least {}", period_name,
        std::lround(period / interval), format_value(interval), static_cast<int>(minimum_rows)));
}

/// One warning line for a period other than the run's cycle, or a regurgitant fraction no valve has;
/// empty when there is neither.
std::string period_warning(const ValveMetrics& metrics, const ReportOptions& options)
{
  const double period = options.settings.period;
  std::string warning;
  if (options.run_period && std::abs(period - *options.run_period) > 1e-9 * *options.run_period)
    warning = (options.period_given ? "--period " : "report.period ") + format_value(period) +
              " s is not the run's cycle (report.period " + format_value(*options.run_period) +
              " s in config.toml)";
  const double rf = metrics.value("regurgitant_fraction");
  if (std::isfinite(rf) && (rf < 0.0 || rf > 100.0))
    warning += (warning.empty() ? "with the period " + format_value(period) + " s: RF " : ": RF ") +
               format_value(rf) + " % is outside 0-100 %";
  return warning.empty() ? warning : warning + "; the metrics are of a " + format_value(period) + " s window";
}

/// The plots of another page of the same cycle copied into `folder` (drawing them again would give the
/// same images, slower), with the script that drew them.
DrawnPlots copy_plots(const fs::path& from, const fs::path& folder)
{
  DrawnPlots copied;
  try {
    for (const PlotCaption& plot : report_plots()) {
      fs::remove(folder / plot.file);
      if (!fs::exists(from / plot.file)) continue;
      fs::copy_file(from / plot.file, folder / plot.file, fs::copy_options::overwrite_existing);
      copied.files.push_back(folder / plot.file);
    }
    if (fs::exists(from / "plot_report.py"))
      fs::copy_file(from / "plot_report.py", folder / "plot_report.py", fs::copy_options::overwrite_existing);
  } catch (const fs::filesystem_error& error) {
    throw RunError(std::string("copying the report's plots: ") + error.what());
  }
  return copied;
}

/// A page's metrics.json in `folder` (made if missing): what its plots and its text are drawn from.
void write_page_document(const Json& doc, const fs::path& folder)
{
  io::create_output_folder(folder);
  // Text that is not UTF-8 (a run folder's name) is replaced rather than refused.
  io::write_file_atomically(folder / "metrics.json",
                            doc.dump(2, ' ', false, Json::error_handler_t::replace) + "\n");
}

/// A page's report.md and report.html in `folder`, beside its metrics.json and `plots`.
void render_page(const Json& doc, const fs::path& folder, const std::vector<fs::path>& plots,
                 const PageTemplates& templates, const std::string& report_root)
{
  const kainjow::mustache::data values = report_template_values(doc, plots, report_root);
  const std::string markdown = templates.markdown.render(values), html = templates.html.render(values);
  io::write_file_atomically(folder / "report.md", markdown);
  io::write_file_atomically(folder / "report.html", html);
}

} // namespace

ReportFiles write_report(const fs::path& run_directory, const ReportOptions& options)
{
  const fs::path series_file = run_directory / "timeseries.csv";
  if (!fs::is_directory(run_directory)) throw InputError(run_directory.string() + ": no such run folder");
  if (!fs::exists(series_file))
    throw InputError(series_file.string() + ": no such file (is this a run folder?)");
  const ValveSeries series = read_valve_series(series_file);
  const PageTemplates templates = load_page_templates("report", options.templates, "report.templates");
  check_period(series, series_file, options);
  std::string run_name = fs::absolute(run_directory).lexically_normal().filename().string();
  if (run_name.empty())
    run_name = fs::absolute(run_directory).lexically_normal().parent_path().filename().string();
  // Every page's document before anything is written: bad input leaves no page behind.
  auto document = [&](int cycle) {
    MetricSettings settings = options.settings;
    settings.cycle = cycle;
    ValveMetrics metrics;
    Json doc;
    try {
      metrics = compute_metrics(series, settings);
      doc = metrics_document(metrics, settings, run_name, run_directory);
      add_ventricle_metrics(doc, series_file, metrics); // runs with the closed loop: V_LV and its loop
      doc["cycles"] = cycle_table(series, settings, metrics.cycle);
    } catch (const std::invalid_argument& error) {
      throw InputError(series_file.string() + ": " + error.what());
    }
    if (options.run_cycles) doc["cycle"]["of"] = std::max(*options.run_cycles, metrics.cycles);
    doc["periodicity"] = periodicity_summary(doc["cycles"]);
    return std::pair(std::move(metrics), std::move(doc));
  };
  // A run's end of cycle N before its reported cycle (report.cycle beyond N) writes cycle N's folder only.
  const int whole = whole_cycles(series, options.settings.period);
  const bool reported_now =
      whole < 1 || options.cycle_folders != CycleFolders::last || options.settings.cycle <= whole;
  std::optional<std::pair<ValveMetrics, Json>> reported;
  if (reported_now) reported = document(options.settings.cycle);
  std::vector<std::pair<ValveMetrics, Json>> pages; // the cycles' own folders
  if (options.cycle_folders == CycleFolders::every)
    for (int c = 1; c <= whole; ++c)
      pages.push_back(reported && c == reported->first.cycle ? *reported : document(c));
  else if (options.cycle_folders == CycleFolders::last)
    pages.push_back(reported && whole == reported->first.cycle ? *reported : document(whole));

  ReportFiles files;
  files.warning = period_warning(reported ? reported->first : pages.back().first, options);
  if (!files.warning.empty()) base::Logger::global().warn(files.warning);
  const fs::path folder = options.output.empty() ? run_directory / "report" : options.output;
  // Every page's metrics.json first; then the plots, all pages' by one Python; then their text.
  std::vector<fs::path> page_folders;
  fs::path reported_folder; // the reported cycle's own folder, when written: its plots serve report/ too
  for (const auto& [metrics, doc] : pages) {
    page_folders.push_back(folder / fmt::format("cycle_{}", metrics.cycle));
    write_page_document(doc, page_folders.back());
    if (reported && metrics.cycle == reported->first.cycle) reported_folder = page_folders.back();
  }
  files.directory = folder;
  const bool report_page = !(options.cycle_folders == CycleFolders::last && reported_folder.empty());
  if (!report_page) files.directory = page_folders.back();
  if (report_page) write_page_document(reported->second, folder);
  std::vector<fs::path> drawn_folders; // the pages whose plots are drawn
  for (const fs::path& page : page_folders)
    if (options.cycle_plots || page == reported_folder) drawn_folders.push_back(page);
  if (report_page && reported_folder.empty()) drawn_folders.push_back(folder);
  const std::vector<DrawnPlots> drawn =
      draw_page_plots(options.plots, options.python, series_file, drawn_folders, report_plots());
  auto drawn_in = [&](const fs::path& page) {
    for (std::size_t i = 0; i < drawn_folders.size(); ++i)
      if (drawn_folders[i] == page) return drawn[i].files;
    return std::vector<fs::path>{};
  };
  for (std::size_t i = 0; i < pages.size(); ++i) {
    if (!options.cycle_plots && page_folders[i] != reported_folder)
      remove_plots(page_folders[i], report_plots()); // an earlier report's images of this cycle
    render_page(pages[i].second, page_folders[i], drawn_in(page_folders[i]), templates, "../");
    files.cycle_pages.push_back(page_folders[i] / "report.html");
  }
  if (report_page) {
    files.plots = reported_folder.empty() ? drawn_in(folder) : copy_plots(reported_folder, folder).files;
    render_page(reported->second, folder, files.plots, templates, "");
  }
  const auto& shown = reported ? *reported : pages.back();
  files.reported_cycle = shown.first.cycle;
  files.cycles = shown.second.at("cycle").at("of").get<int>();
  files.json = files.directory / "metrics.json";
  files.markdown = files.directory / "report.md";
  files.html = files.directory / "report.html";
  if (!drawn.empty() && !drawn.front().problem.empty()) throw RunError(drawn.front().problem);
  return files;
}

} // namespace ibvalve::hemodynamics
