#pragma once
// `ibvalve report`: metrics.json, report.md and report.html (plots by matplotlib) for one run folder,
// and the metric settings as case-file keys ([report] table). The Markdown and HTML are laid out by
// Mustache templates (hemodynamics/templates/, built in; a user's own with report.templates).
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include "hemodynamics/metrics.hpp"
#include "hemodynamics/page_templates.hpp"
#include "hemodynamics/plotting.hpp"
#include "io/config.hpp"
#include "io/key_binder.hpp"

namespace ibvalve::hemodynamics {

/// JSON as metrics.json holds it: members keep the order they were written in.
using Json = nlohmann::ordered_json;

/// What the [report] table sets: the metric settings, whether to draw the plots, the templates folder.
struct ReportSettings {
  MetricSettings metrics;
  bool plots = true;
  bool cycle_plots = true; // each cycle's own page (report/cycle_N/) drawn too, not only the reported one
  std::filesystem::path templates; // empty = the built-in templates
};

/// The [report] keys (period, cycle, thresholds, closure rule, density, plots, templates) under `prefix`,
/// bound to `r` (io/key_binder.hpp): declared into a schema, or read from a case (then the checks a
/// schema cannot express, closed below open area, are made).
void bind_report(io::KeyBinder& keys, ReportSettings& r, const std::string& prefix = "report");
/// A case's report.templates, when given, must be a folder whose templates parse: refused before the run
/// rather than after it.
void check_report_templates(const io::KeyBinder& keys, const ReportSettings& r);

/// The [report] table a run folder's resolved config.toml records.
struct RecordedReport {
  ReportSettings report;
  /// report.period as the run recorded it (its cycle), if it records one.
  std::optional<double> period;
};
/// The settings of a run folder's config.toml, its [report] table validated against the [report] schema
/// (the density from fluid.density), defaults for keys it lacks (or when there
/// is no config.toml or no [report] table). A key of the wrong type or value is an InputError naming the
/// file; report.templates relative to the run folder.
RecordedReport recorded_report(const std::filesystem::path& run_directory);
/// recorded_report(run_directory).report.metrics.
MetricSettings metric_settings_from_run(const std::filesystem::path& run_directory);

/// Which cycles of the series get a report folder of their own, <output>/cycle_N/ (N counted from 1),
/// beside the reported cycle's report in <output> itself.
enum class CycleFolders {
  every, // every whole cycle (`ibvalve report`, a run that reports once at its end)
  last,  // the last whole cycle only (a run's end of cycle N); <output> is written when N is the reported one
  none,  // none (a run shorter than a cycle: its one window)
};

struct ReportOptions {
  MetricSettings settings;
  std::string python = default_python(); // an interpreter with matplotlib and numpy
  bool plots = true;
  /// With `plots`: every cycle page's plots, or only the reported cycle's (its own folder and <output>).
  bool cycle_plots = true;
  /// The settings' period was given on the command line (--period): messages name the option.
  bool period_given = false;
  /// The run's own cycle (RecordedReport::period), which a given period is checked against.
  std::optional<double> run_period;
  /// A folder holding report.html.tpl and/or report.md.tpl, used instead of the built-in ones; empty =
  /// the built-in ones.
  std::filesystem::path templates;
  /// The report's folder; empty = <run>/report.
  std::filesystem::path output;
  CycleFolders cycle_folders = CycleFolders::every;
  /// The cycles of the whole run, for the pages' "cycle N of M", when a run reports at each cycle's end
  /// (its series then holds only the cycles so far); unset = the series' whole cycles.
  std::optional<int> run_cycles;
};

struct ReportFiles {
  /// The reported cycle's page (<output>; its cycle's own folder when a run's end of cycle N wrote only
  /// that one).
  std::filesystem::path directory, json, markdown, html;
  std::vector<std::filesystem::path> plots;
  /// report.html of each cycle's own folder written, in cycle order.
  std::vector<std::filesystem::path> cycle_pages;
  int reported_cycle = 0, cycles = 0; // the reported cycle (from 1) and the run's cycles (run_cycles)
  /// One line (also logged as a warning) when the period is not the run's cycle or a metric is outside
  /// its physical range (RF outside 0-100 %), else empty.
  std::string warning;
};

/// Where a run came from and what it was given: "run" (its run.json: case file, the ibvalve version and
/// commit that ran it, when it started, on how many ranks, its restarts), "report" (the version, commit
/// and time of this report) and "inputs" (every key of its config.toml but the output, log, petsc, run,
/// report and checkpoint tables, as TOML writes the value).
Json provenance_document(const std::filesystem::path& run_directory);

/// metrics.json as a document: the cycle (its number from 1 and the series' whole cycles), settings,
/// the headline figures beside their published ranges and the plausibility checks
/// (report_layout.hpp), phases, metrics (value, unit, symbol, description, note, group), notes,
/// provenance. Metrics from <run>/extra_metrics.json (an object of key -> number or key -> {value,
/// unit, symbol, description, note, synthetic_data}) are appended: this is how a 3-D run adds structural
/// metrics (fit error, strain and stress variation, displacements) it computes itself; synthetic_data
/// (true: measured against generated data) is kept for the comparison to say so.
Json metrics_document(const ValveMetrics& metrics, const MetricSettings& settings,
                      const std::string& run_name, const std::filesystem::path& run_directory);

/// Reads <run>/timeseries.csv, computes the metrics and writes the report: <output>/{metrics.json,
/// report.md, report.html, plot_report.py, *.png} of the reported cycle (options.settings.cycle), and the
/// same for the cycles options.cycle_folders names in <output>/cycle_N/. Each page carries the table of
/// its cycle and the ones before it (V_F, TPG, P_Wk at the start and end). Bad input (missing file,
/// missing column, bad line, a period longer than the series or holding fewer than 10 of its rows, a
/// cycle the series does not hold, a missing templates folder or a template that does not parse) is an
/// InputError raised before anything is written; a plotting failure is a RunError after the metrics,
/// Markdown and HTML (without plots) are written.
ReportFiles write_report(const std::filesystem::path& run_directory, const ReportOptions& options);

/// One line of a report's figures for a run's closing summary, from its metrics.json: "V_F ... mL, RF
/// ... %, TPG ... mmHg, EOA ... cm^2, E_L ... mJ" (a figure without a value "missing"), then the peak
/// velocity at full opening when the run measured one (a 3-D run: "u_max,FO ... m/s").
std::string metrics_summary(const std::filesystem::path& metrics_json);

/// A value for tables: 4 significant digits (or "missing").
std::string format_value(double value);
/// Every digit of a value: the shortest text that reads back as the same double (std::to_chars), or
/// "null" when it is not finite.
std::string exact_value(double value);
/// A CSV field: as it is, or in double quotes (quotes doubled) when it holds a comma, quote or line break.
std::string csv_field(const std::string& text);

} // namespace ibvalve::hemodynamics
