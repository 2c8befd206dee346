#pragma once
// `ibvalve compare RUN_DIR...`: every metric per case (the study's Table 7), the 12-criterion scaled
// ranking (its Table 8) in rank order, and the inputs that differ between the cases, as Markdown, CSV
// and HTML.
//
// Ranking (docs/reference.md, "Hemodynamic metrics"): for each criterion the best case scores 1 and
// the worst 0, linearly in between; a case's total is the sum; cases are ranked by total. When the cases'
// values of a criterion all lie within tie_tolerance of the largest in size, they tie and all score 1:
// min-max scaling would otherwise turn a round-off difference (1e-9) into a whole point. A criterion missing
// for any case (e.g. the fit error of a lumped run) is left out of the ranking for all cases, and the output
// says so; so is a criterion the user leaves out (--leave-out, a study's leave_out). Which direction is
// "best" is ibvalve's reading of the study, listed in ranking_criteria() and docs/hemodynamics.md.
//
// Uncertainty: a metric of metrics.json may carry "uncertainty", its standard uncertainty u (same unit;
// docs/hemodynamics.md, "Comparison"). Where a criterion's values have one, a difference counts only
// when it exceeds tie_coverage x sqrt(u_a^2 + u_b^2): the sorted values are chained into groups
// whose neighbours differ by no more, each group's members score as their mean value, and the groups
// are scaled as above (one group: all tie at 1). The ranking's stability is then estimated by drawing
// every uncertain metric from a normal distribution about its value, rank_stability_draws times
// (fixed seed), and ranking each draw as if it were exact: how often each case keeps its rank, and how
// often the whole order holds. A rank shared by m tied cases claims no order among them: a case keeps
// it when it lands anywhere in the m places. A metric may also carry "uncertainty_shared", the signed
// shifts (variant - case) of sources common to the cases, such as a second grid applied to all: for two
// cases such a source contributes the change it makes to their difference, shift_a - shift_b, in place
// of sqrt(shift_a^2 + shift_b^2), and in the draws it is one normal factor for all cases and criteria,
// each moved by that factor times its own shift.
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hemodynamics/metrics.hpp"
#include "hemodynamics/report.hpp"

namespace ibvalve::hemodynamics {

struct Criterion {
  std::string key;   // metrics.json key
  std::string label; // as in the study's table
  bool higher_is_better = false;
};
/// Relative spread below which a criterion's values tie: 1e-3, ten times the run-to-run differences of
/// a 3-D cycle's metrics between 1 and 2 ranks (1.4e-4 at most, tests/regression/README.md) and a tenth
/// of the 1 % change the nightly regression must detect.
inline constexpr double tie_tolerance = 1e-3;
/// Two values tie when they differ by at most this many combined standard uncertainties (2: about
/// 95 % coverage for normal errors).
inline constexpr double tie_coverage = 2.0;
/// Draws of the ranking's stability estimate.
inline constexpr int rank_stability_draws = 10000;
/// The 12 criteria, in the study's order.
const std::vector<Criterion>& ranking_criteria();

struct CaseResult {
  std::string name;
  std::filesystem::path run_directory;
  Json metrics; // the "metrics" object of metrics.json
  /// The analysed cycle (metrics.json's phases cycle_start, cycle_end), for the overlaid curves.
  std::optional<double> cycle_start, cycle_end;
  /// The run's inputs as its config.toml records them (key, value with its unit), for what differs
  /// between the cases; empty without a config.toml.
  std::vector<std::pair<std::string, std::string>> inputs;
};

/// A run folder's metrics: report/metrics.json (the reported cycle's) when present, otherwise computed
/// from timeseries.csv with the settings of the run's config.toml; and its inputs from config.toml.
/// InputError for a folder that has neither metrics.json nor timeseries.csv.
CaseResult load_case(const std::filesystem::path& run_directory);
/// The value of metric `key` of a case when it is a finite number.
std::optional<double> metric_value(const CaseResult& c, const std::string& key);
/// The text `field` ("unit", "symbol") of metric `key` of a case, or empty.
std::string metric_text(const CaseResult& c, const std::string& key, const char* field);
/// Cases with the same name (e.g. two runs of one case file) told apart: every case's name gains its
/// folder's name, "W1FD1 (run_a)", when any two names coincide.
void distinguish_case_names(std::span<CaseResult> cases);

struct RankingRow {
  std::string name;
  std::vector<std::optional<double>> scores; // per criterion; empty when the criterion is left out
  double total = 0.0;
  int rank = 0;
  double rank_held = 1.0; // the fraction of draws in which the case keeps `rank` (1 without uncertainties)
};
struct Ranking {
  std::vector<bool> used;            // per criterion
  std::vector<std::string> left_out; // "fit_error (missing for: a, b)", "fit_error (left out on request)"
  std::vector<RankingRow> rows;      // in the order of the cases
  std::vector<std::size_t> by_rank;  // the rows' indices in rank order (tied cases in the cases' order)
  bool uncertain = false;            // some ranked metric carries an uncertainty
  double order_held = 1.0;           // the fraction of draws that keep every case's rank
};
/// The ranking of `cases` on every criterion but those `leave_out` names (criterion keys;
/// std::invalid_argument for a key that is no criterion: check_criteria first).
Ranking rank_cases(std::span<const CaseResult> cases, std::span<const std::string> leave_out = {});
/// An empty string when every key names a ranking criterion, else why not ("'x' is no ranking
/// criterion (fit_error, ...)").
std::string check_criteria(std::span<const std::string> keys);

/// What the ranking's figures rest on that a reader must know: one line per criterion measured against
/// synthetic data (a metric with "synthetic_data": true, the fit error against samples drawn from a
/// law's own curves, which that law wins by construction), naming the cases.
std::vector<std::string> criterion_notes(std::span<const CaseResult> cases, const Ranking& ranking);

/// The inputs that differ between the cases (their config.toml keys, but name and the output, log,
/// run and checkpoint tables): key and each case's value ("(unset)" where a case lacks the key), in the
/// order of first appearance.
std::vector<std::pair<std::string, std::vector<std::string>>>
differing_inputs(std::span<const CaseResult> cases);

struct ComparisonOptions {
  std::filesystem::path templates;       // a folder of comparison templates; empty: the built-in ones
  std::string python = default_python(); // an interpreter with matplotlib and numpy
  bool plots = true;
  std::vector<std::string> leave_out; // criteria (their keys) left out of the ranking
};
struct ComparisonFiles {
  std::filesystem::path markdown, metrics_csv, ranking_csv, html;
  std::vector<std::filesystem::path> plots; // the overlaid curves drawn
};
/// The overlaid curves' files and captions, in the order the pages show them.
inline constexpr PlotCaption comparison_plots[] = {
    {"flow.png", "Flow through the valve Q(t), each case over its analysed cycle"},
    {"pressure_difference.png", "P_nlv - P_nao across the leaflets"},
    {"orifice_area.png", "Geometric orifice area"},
};
/// Writes comparison.md, comparison.html (laid out by the comparison templates: the built-in ones, or
/// those of `options.templates`, see page_templates.hpp: the inputs that differ between the cases, the
/// metrics, the ranking in rank order and the notes on its criteria), metrics.csv and ranking.csv (in
/// rank order) into
/// `output_directory`, and with `options.plots` the overlaid curves of the cases' time series (their
/// timeseries.csv, each over its analysed cycle: flow.png, pressure_difference.png and orifice_area.png
/// for the columns the series have, drawn by plot_report.py --compare with `options.python`). A templates
/// folder that is missing or holds a template that does not parse is an InputError raised before
/// anything is written, and so is a criterion in options.leave_out that is none; a plotting failure is a
/// RunError after the pages (without plots) are written.
ComparisonFiles write_comparison(std::span<const CaseResult> cases,
                                 const std::filesystem::path& output_directory,
                                 const ComparisonOptions& options = {});

} // namespace ibvalve::hemodynamics
