#include "hemodynamics/convergence_study.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "base/errors.hpp"
#include "hemodynamics/report.hpp"
#include "hemodynamics/text_template.hpp"
#include "io/config.hpp"
#include "io/files.hpp"

namespace ibvalve::hemodynamics {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void bad_key(const toml::node* node, const fs::path& file, std::string_view key,
                          std::string_view message)
{
  throw InputError(io::node_location(node, file) + ": " + std::string(key) + ": " + std::string(message));
}

/// An element of an array as a finite number, or nothing; with `positive_integer`, only a positive integer.
std::optional<double> element_number(const toml::node& element, bool positive_integer)
{
  if (positive_integer) {
    if (!element.is_integer() || *element.value<std::int64_t>() <= 0) return std::nullopt;
    return static_cast<double>(*element.value<std::int64_t>());
  }
  const std::optional<double> v = element.is_number() ? element.value<double>() : std::nullopt;
  return v && std::isfinite(*v) ? v : std::nullopt;
}

/// The array at `key`: `count` numbers (any number when count is 0), positive integers with `integers`.
std::vector<double> numbers_at(const toml::table& root, const fs::path& file, const char* key,
                               std::size_t count, bool integers, bool required = true)
{
  const toml::node* node = root.at_path(key).node();
  if (!node) {
    if (!required) return {};
    bad_key(nullptr, file, key, "missing: the grid convergence study reads each run's grid from it");
  }
  const std::string expected = integers ? (count ? fmt::format("{} positive integers", count)
                                                 : std::string("a list of positive integers"))
                                        : fmt::format("{} numbers (cm)", count);
  const toml::array* array = node->as_array();
  if (!array || (count && array->size() != count)) bad_key(node, file, key, "expected " + expected);
  std::vector<double> values;
  for (const toml::node& element : *array) {
    const std::optional<double> v = element_number(element, integers);
    if (!v) bad_key(node, file, key, "expected " + expected);
    values.push_back(*v);
  }
  return values;
}

/// Whether a and b agree within spacing_tolerance of the larger.
bool same_spacing(double a, double b)
{
  return std::abs(a - b) <= spacing_tolerance * std::max(std::abs(a), std::abs(b));
}

} // namespace

double finest_grid_spacing(const fs::path& config_file)
{
  const toml::table root = io::parse_toml_file(config_file);
  const auto cells = numbers_at(root, config_file, "fluid.cells", 3, true);
  const auto lower = numbers_at(root, config_file, "fluid.lower", 3, false);
  const auto upper = numbers_at(root, config_file, "fluid.upper", 3, false);
  const auto ratios = numbers_at(root, config_file, "nested.ratios", 0, true, false);
  double refinement = 1.0;
  for (double r : ratios) refinement *= r;
  std::array<double, 3> h{};
  for (std::size_t axis = 0; axis < 3; ++axis) {
    if (!(upper[axis] > lower[axis]))
      bad_key(root.at_path("fluid.upper").node(), config_file, "fluid.upper",
              "must exceed fluid.lower on every axis");
    h[axis] = (upper[axis] - lower[axis]) / cells[axis] / refinement;
  }
  if (!same_spacing(h[0], h[1]) || !same_spacing(h[0], h[2]))
    bad_key(root.at_path("fluid.cells").node(), config_file, "fluid.cells",
            fmt::format("the finest cells are not cubes ({} x {} x {} cm from fluid.lower, fluid.upper, "
                        "fluid.cells and nested.ratios): a grid convergence study needs one spacing per grid",
                        exact_value(h[0]), exact_value(h[1]), exact_value(h[2])));
  return h[0];
}

namespace {

std::vector<GridRun> load_runs(std::span<const fs::path> run_directories)
{
  if (run_directories.size() < 2)
    throw InputError(
        fmt::format("ibvalve convergence: {} run folder given; a grid convergence study needs at "
                    "least two (three for an observed order)",
                    run_directories.size()));
  std::vector<CaseResult> cases;
  std::vector<double> spacings;
  for (const auto& directory : run_directories) {
    cases.push_back(load_case(directory));
    const fs::path config = directory / "config.toml";
    if (!fs::exists(config))
      throw InputError(config.string() +
                       ": no such file (a run's grid spacing is read from its config.toml)");
    spacings.push_back(finest_grid_spacing(config));
  }
  distinguish_case_names(cases);
  std::vector<GridRun> runs;
  for (std::size_t i = 0; i < cases.size(); ++i) runs.push_back({std::move(cases[i]), spacings[i]});
  std::stable_sort(runs.begin(), runs.end(),
                   [](const auto& a, const auto& b) { return a.spacing < b.spacing; });
  for (std::size_t i = 1; i < runs.size(); ++i)
    if (same_spacing(runs[i - 1].spacing, runs[i].spacing))
      throw InputError(fmt::format("{} and {}: the same grid spacing, {} cm: a grid convergence study needs "
                                   "runs on different grids",
                                   (runs[i - 1].run.run_directory / "config.toml").string(),
                                   (runs[i].run.run_directory / "config.toml").string(),
                                   exact_value(runs[i].spacing)));
  return runs;
}

} // namespace

ConvergenceStudy study_grid_convergence(std::span<const fs::path> run_directories)
{
  ConvergenceStudy study;
  study.runs = load_runs(run_directories);
  std::vector<std::string> keys; // in the order of first appearance, finest run first
  for (const auto& r : study.runs)
    for (const auto& [key, value] : r.run.metrics.items())
      if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
  std::vector<double> spacings;
  for (const auto& r : study.runs) spacings.push_back(r.spacing);
  for (const auto& key : keys) {
    MetricConvergence m{key, {}, {}, {}, {}};
    std::vector<std::string> missing;
    for (const auto& r : study.runs) {
      const auto v = metric_value(r.run, key);
      if (!v) missing.push_back(r.run.name);
      m.values.push_back(v.value_or(0.0));
      if (m.symbol.empty()) m.symbol = metric_text(r.run, key, "symbol");
      if (m.unit.empty()) m.unit = metric_text(r.run, key, "unit");
    }
    if (!missing.empty()) {
      study.left_out.push_back(
          fmt::format("{} (missing or not a finite number in: {})", key, fmt::join(missing, ", ")));
      continue;
    }
    m.result = grid_convergence(spacings, m.values);
    study.metrics.push_back(std::move(m));
  }
  return study;
}

namespace {

Json optional_number(const std::optional<double>& v)
{
  return v ? Json(*v) : Json();
}

std::vector<double> refinement_ratios(const ConvergenceStudy& study)
{
  std::vector<double> r;
  for (std::size_t i = 1; i < study.runs.size(); ++i)
    r.push_back(study.runs[i].spacing / study.runs[i - 1].spacing);
  return r;
}

/// ln(r21)/ln(r32): R below it (and above 0) is monotone convergence (grid_convergence.hpp).
std::optional<double> monotone_bound(const ConvergenceStudy& study)
{
  const auto r = refinement_ratios(study);
  if (r.size() < 2) return std::nullopt;
  return std::log(r[0]) / std::log(r[1]);
}

Json convergence_json(const ConvergenceStudy& study)
{
  Json doc{{"ibvalve_convergence", 1},
           {"method", "Celik, Ghia, Roache, Freitas, Coleman & Raad (2008), J. Fluids Eng. 130:078001, "
                      "with a conservative uncertainty where the grids do not converge monotonically "
                      "(docs/hemodynamics.md, \"Grid convergence\")"}};
  Json grids = Json::array();
  for (const auto& r : study.runs)
    grids.push_back({{"run", r.run.name},
                     {"folder", fs::absolute(r.run.run_directory).lexically_normal().string()},
                     {"spacing_cm", r.spacing}});
  doc["grids"] = grids;
  doc["refinement_ratios"] = refinement_ratios(study);
  doc["monotone_bound"] = optional_number(monotone_bound(study));
  Json metrics = Json::object();
  for (const auto& m : study.metrics) {
    const GridConvergence& g = m.result;
    metrics[m.key] = {
        {"symbol", m.symbol},
        {"unit", m.unit},
        {"values", m.values},
        {"class", to_string(g.kind)},
        {"rule", to_string(g.rule)},
        {"R", optional_number(g.R)},
        {"p", optional_number(g.p)},
        {"p_iterations", g.order_iterations},
        {"assumed_order", g.rule == UncertaintyRule::assumed_order ? Json(two_grid_assumed_order) : Json()},
        {"phi_ext", optional_number(g.phi_ext)},
        {"e_a", optional_number(g.e_a)},
        {"e_ext", optional_number(g.e_ext)},
        {"safety_factor", g.safety_factor},
        {"gci", optional_number(g.gci)},
        {"gci_in_unit", g.uncertainty}};
  }
  doc["metrics"] = metrics;
  doc["left_out"] = study.left_out;
  return doc;
}

std::string csv_number(const std::optional<double>& v)
{
  return v ? exact_value(*v) : std::string();
}

std::string convergence_csv(const ConvergenceStudy& study)
{
  std::string csv = "metric,symbol,unit";
  for (const auto& r : study.runs) csv += "," + csv_field(r.run.name);
  csv += ",R,class,rule,p,phi_ext,e_a,e_ext,safety_factor,gci,gci_in_unit\n";
  for (const auto& m : study.metrics) {
    const GridConvergence& g = m.result;
    csv += fmt::format("{},{},{}", csv_field(m.key), csv_field(m.symbol), csv_field(m.unit));
    for (double v : m.values) csv += "," + exact_value(v);
    csv +=
        fmt::format(",{},{},{},{},{},{},{},{},{},{}\n", csv_number(g.R), to_string(g.kind), to_string(g.rule),
                    csv_number(g.p), csv_number(g.phi_ext), csv_number(g.e_a), csv_number(g.e_ext),
                    exact_value(g.safety_factor), csv_number(g.gci), exact_value(g.uncertainty));
  }
  return csv;
}

/// Six significant digits: a grid study's values often differ in the fourth.
std::string precise(double v)
{
  return fmt::format("{:.6g}", v);
}

std::string shown(const std::optional<double>& v)
{
  return v ? format_value(*v) : std::string("–");
}

std::string percent(const std::optional<double>& v)
{
  return v ? format_value(100.0 * *v) + " %" : std::string("–");
}

std::string metric_label(const MetricConvergence& m)
{
  return m.symbol.empty() ? fmt::format("`{}`", markdown_escaped(m.key))
                          : fmt::format("{} (`{}`)", markdown_escaped(m.symbol), markdown_escaped(m.key));
}

std::string grids_markdown(const ConvergenceStudy& study)
{
  std::string md = "## Grids, finest first\n\n| grid | run | folder | h (cm) | ratio to the finer |\n"
                   "|---|---|---|---|---|\n";
  const auto ratios = refinement_ratios(study);
  for (std::size_t i = 0; i < study.runs.size(); ++i)
    md += fmt::format("| {} | {} | {} | {} | {} |\n", i + 1, markdown_escaped(study.runs[i].run.name),
                      markdown_escaped(study.runs[i].run.run_directory.string()),
                      precise(study.runs[i].spacing), i == 0 ? std::string("–") : precise(ratios[i - 1]));
  md += "\n";
  if (const auto bound = monotone_bound(study))
    md +=
        fmt::format("R = (phi2 - phi1)/(phi3 - phi2) on the three finest grids; they converge monotonically "
                    "when 0 < R < ln(r21)/ln(r32) = {}.{}\n\n",
                    precise(*bound), study.runs.size() > 3 ? " Coarser grids are listed, not used." : "");
  else
    md += fmt::format("Two grids: no order can be observed. The GCI assumes order {} with a factor of safety "
                      "of {} (Roache 1994).\n\n",
                      two_grid_assumed_order, conservative_safety_factor);
  if (std::any_of(ratios.begin(), ratios.end(), [](double r) { return r < 1.3; }))
    md += "A refinement ratio is below 1.3, the least Celik et al. (2008) recommend: the differences between "
          "grids may be too small to tell discretization error from other errors.\n\n";
  return md;
}

std::string metrics_markdown(const ConvergenceStudy& study)
{
  std::string md = "## Metrics\n\n| metric | unit |";
  for (const auto& r : study.runs) md += " " + markdown_escaped(r.run.name) + " |";
  md += " R | class | p | φ_ext | e_a | e_ext | GCI | GCI (unit) |\n|---|---|";
  for (std::size_t i = 0; i < study.runs.size(); ++i) md += "---|";
  md += "---|---|---|---|---|---|---|---|\n";
  for (const auto& m : study.metrics) {
    const GridConvergence& g = m.result;
    md += fmt::format("| {} | {} |", metric_label(m), markdown_escaped(m.unit));
    for (double v : m.values) md += " " + precise(v) + " |";
    md += fmt::format(" {} | {} | {} | {} | {} | {} | {} | {} |\n", shown(g.R), to_string(g.kind), shown(g.p),
                      g.phi_ext ? precise(*g.phi_ext) : std::string("–"), percent(g.e_a), percent(g.e_ext),
                      percent(g.gci), format_value(g.uncertainty));
  }
  if (study.metrics.empty()) md += "\n(no metric that every run has as a number)\n";
  return md + "\n";
}

/// Why a metric has no Celik et al. estimate.
std::string without_observed_order(const GridConvergence& g)
{
  switch (g.kind) {
  case ConvergenceClass::oscillatory:
    return "oscillatory (R < 0)";
  case ConvergenceClass::divergent:
    return "divergent (R at or beyond the bound: no positive order fits)";
  case ConvergenceClass::indeterminate:
    return "indeterminate (the two finest grids agree exactly)";
  case ConvergenceClass::unchanged:
    return "unchanged on every grid: no discretization error is seen";
  case ConvergenceClass::two_grids:
    return "two grids";
  case ConvergenceClass::monotone:
    break;
  }
  return fmt::format(
      "monotone, but the observed order's fixed-point iteration did not converge ({} iterations)",
      g.order_iterations);
}

/// Where the GCI is not Celik et al.'s: which rule gave it and why.
std::string notes_markdown(const ConvergenceStudy& study)
{
  std::string md = "## Where the grids do not converge monotonically\n\n";
  bool any = false;
  for (const auto& m : study.metrics) {
    const GridConvergence& g = m.result;
    if (g.rule == UncertaintyRule::richardson) continue;
    any = true;
    const std::string why = without_observed_order(g);
    if (g.rule == UncertaintyRule::none) {
      md += fmt::format("- {}: {}: uncertainty 0 {}.\n", metric_label(m), why, markdown_escaped(m.unit));
      continue;
    }
    const std::string how =
        g.rule == UncertaintyRule::range
            ? fmt::format(
                  "uncertainty {} × the largest change of the finest value over the three finest grids",
                  conservative_safety_factor)
            : fmt::format("GCI with the assumed order {} and a factor of safety of {}",
                          two_grid_assumed_order, conservative_safety_factor);
    md += fmt::format("- {}: {}; {}: {} {} (GCI {}); no observed order or extrapolate.\n", metric_label(m),
                      why, how, format_value(g.uncertainty), markdown_escaped(m.unit), percent(g.gci));
  }
  if (!any) md += "Every metric converges monotonically: each GCI is Celik et al.'s.\n";
  md += "\n";
  if (!study.left_out.empty()) {
    md += "## Left out\n\n";
    for (const auto& l : study.left_out) md += "- " + markdown_escaped(l) + "\n";
    md += "\n";
  }
  return md;
}

std::string convergence_markdown(const ConvergenceStudy& study)
{
  std::string md = fmt::format("# ibvalve grid convergence of {} runs\n\n", study.runs.size());
  md +=
      "Observed order p, Richardson extrapolate φ_ext and grid convergence index (GCI) of the finest grid's "
      "value after Celik, Ghia, Roache, Freitas, Coleman & Raad (2008), J. Fluids Eng. 130:078001: "
      "e_a = |(phi1 - phi2)/phi1|, e_ext = |(φ_ext - phi1)/φ_ext|, GCI = 1.25 e_a/(r21^p - 1), also in the "
      "metric's unit. Where the grids do not converge monotonically there is no p or φ_ext and the "
      "uncertainty is a conservative one, as listed below (docs/hemodynamics.md, \"Grid convergence\").\n\n";
  return md + grids_markdown(study) + metrics_markdown(study) + notes_markdown(study);
}

} // namespace

ConvergenceFiles write_grid_convergence(const ConvergenceStudy& study, const fs::path& output_directory)
{
  const std::string markdown = convergence_markdown(study), csv = convergence_csv(study);
  const std::string json = convergence_json(study).dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
  io::create_output_folder(output_directory);
  ConvergenceFiles files{output_directory / "convergence.md", output_directory / "convergence.csv",
                         output_directory / "convergence.json"};
  io::write_file_atomically(files.markdown, markdown);
  io::write_file_atomically(files.csv, csv);
  io::write_file_atomically(files.json, json);
  return files;
}

} // namespace ibvalve::hemodynamics
