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
  std::filesystem::path templates; // empty = the built-in templates
};

/// The [report] keys (period, cycle, thresholds, closure rule, density, plots, templates) under `prefix`,
/// bound to `r` (io/key_binder.hpp): declared into a schema, or read from a case (then the checks a
/// schema cannot express, closed below open area, are made).
void bind_report(io::KeyBinder& keys, ReportSettings& r, const std::string& prefix = "report");
/// The same keys declared into `schema`.
void add_report_schema(io::Schema& schema, const std::string& prefix = "report");
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

struct ReportOptions {
  MetricSettings settings;
  std::string python = default_python(); // an interpreter with matplotlib and numpy
  bool plots = true;
  /// The settings' period was given on the command line (--period): messages name the option.
  bool period_given = false;
  /// The run's own cycle (RecordedReport::period), which a given period is checked against.
  std::optional<double> run_period;
  /// A folder holding report.html.tpl and/or report.md.tpl, used instead of the built-in ones; empty =
  /// the built-in ones.
  std::filesystem::path templates;
};

struct ReportFiles {
  std::filesystem::path directory, json, markdown, html;
  std::vector<std::filesystem::path> plots;
  /// One line (also logged as a warning) when the period is not the run's cycle or a metric is outside
  /// its physical range (RF outside 0-100 %), else empty.
  std::string warning;
};

/// Where a run came from and what it was given: "run" (its run.json: case file, the ibvalve version and
/// commit that ran it, when it started, on how many ranks, its restarts), "report" (the version, commit
/// and time of this report) and "inputs" (every key of its config.toml but the output, log, petsc, run,
/// report and checkpoint tables, as TOML writes the value).
Json provenance_document(const std::filesystem::path& run_directory);

/// metrics.json as a document: settings, phases, metrics (value, unit, symbol, description, note),
/// notes, provenance. Metrics from <run>/extra_metrics.json (an object of key -> number or key -> {value,
/// unit, symbol, description}) are appended: this is how a 3-D run adds structural metrics (fit error, strain
/// and stress variation, displacements) it computes itself.
Json metrics_document(const ValveMetrics& metrics, const MetricSettings& settings,
                      const std::string& run_name, const std::filesystem::path& run_directory);

/// Reads <run>/timeseries.csv, computes the metrics and writes <run>/report/{metrics.json, report.md,
/// report.html, plot_report.py, *.png}. Bad input (missing file, missing column, bad line, a period
/// longer than the series or holding fewer than 10 of its rows, a missing templates folder or a template
/// that does not parse) is an InputError raised before anything is written; a plotting failure is a
/// RunError after the metrics, Markdown and HTML (without plots) are written.
ReportFiles write_report(const std::filesystem::path& run_directory, const ReportOptions& options);

/// A value for tables: 4 significant digits (or "missing").
std::string format_value(double value);
/// Every digit of a value: the shortest text that reads back as the same double (std::to_chars), or
/// "null" when it is not finite.
std::string exact_value(double value);
/// A CSV field: as it is, or in double quotes (quotes doubled) when it holds a comma, quote or line break.
std::string csv_field(const std::string& text);

} // namespace ibvalve::hemodynamics
