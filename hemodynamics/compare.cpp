#include "hemodynamics/compare.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "base/errors.hpp"
#include "hemodynamics/report.hpp"
#include "io/files.hpp"

namespace ibvalve::hemodynamics {

namespace fs = std::filesystem;

const std::vector<Criterion>& ranking_criteria()
{
  static const std::vector<Criterion> criteria{
      {"fit_error", "fit error", false},
      {"max_orifice_area", "opening orifice", true},
      {"opening_duration", "opening duration", false},
      {"closing_duration", "closing duration", false},
      {"forward_volume", "forward volume", true},
      {"regurgitant_volume", "regurgitant volume", false},
      {"strain_variation", "strain variation (belly - top-centre)", false},
      {"stress_variation", "stress variation (belly - top-centre)", false},
      {"regurgitant_fraction", "RF", false},
      {"transvalvular_pressure_gradient", "TPG", false},
      {"effective_orifice_area", "EOA", true},
      {"energy_loss", "E_L", false},
  };
  return criteria;
}

CaseResult load_case(const fs::path& run_directory)
{
  CaseResult c;
  c.run_directory = run_directory;
  c.name = fs::absolute(run_directory).lexically_normal().filename().string();
  if (c.name.empty())
    c.name = fs::absolute(run_directory).lexically_normal().parent_path().filename().string();
  const fs::path config = run_directory / "config.toml";
  if (fs::exists(config)) {
    const toml::table root = io::parse_toml_file(config);
    if (auto name = root["name"].value<std::string>(); name && !name->empty()) c.name = *name;
  }
  const fs::path stored = run_directory / "report" / "metrics.json";
  Json doc;
  if (fs::exists(stored)) {
    try {
      doc = Json::parse(io::read_text_file(stored));
    } catch (const Json::parse_error& error) {
      throw InputError(stored.string() + ": " + error.what());
    }
  } else {
    const fs::path series_file = run_directory / "timeseries.csv";
    if (!fs::exists(series_file))
      throw InputError(run_directory.string() +
                       ": neither report/metrics.json nor timeseries.csv (not a run folder?)");
    const MetricSettings settings = metric_settings_from_run(run_directory);
    try {
      doc = metrics_document(compute_metrics(read_valve_series(series_file), settings), settings, c.name,
                             run_directory);
    } catch (const std::invalid_argument& error) {
      throw InputError(series_file.string() + ": " + error.what());
    }
  }
  const auto metrics = doc.find("metrics");
  if (metrics == doc.end() || !metrics->is_object())
    throw InputError(stored.string() + ": no \"metrics\" object");
  c.metrics = *metrics;
  if (const auto phases = doc.find("phases"); phases != doc.end() && phases->is_object()) {
    auto instant = [&](const char* key) -> std::optional<double> {
      const auto v = phases->find(key);
      return v != phases->end() && v->is_number() ? std::optional<double>(v->get<double>()) : std::nullopt;
    };
    c.cycle_start = instant("cycle_start");
    c.cycle_end = instant("cycle_end");
  }
  return c;
}

namespace {

/// The member `field` of metric `key`, or nullptr.
const Json* metric_field(const CaseResult& c, const std::string& key, const char* field)
{
  const auto m = c.metrics.find(key);
  if (m == c.metrics.end() || !m->is_object()) return nullptr;
  const auto v = m->find(field);
  return v == m->end() ? nullptr : &*v;
}

std::optional<double> metric_value(const CaseResult& c, const std::string& key)
{
  const Json* v = metric_field(c, key, "value");
  if (!v || !v->is_number() || !std::isfinite(v->get<double>())) return std::nullopt;
  return v->get<double>();
}

std::string metric_text(const CaseResult& c, const std::string& key, const char* field)
{
  const Json* v = metric_field(c, key, field);
  return v && v->is_string() ? v->get<std::string>() : "";
}

/// The text `field` of metric `key` in the first case that has it, else empty.
std::string first_text(std::span<const CaseResult> cases, const std::string& key, const char* field)
{
  for (const auto& c : cases)
    if (auto s = metric_text(c, key, field); !s.empty()) return s;
  return {};
}

/// Every metric key, in the order of first appearance over the cases.
std::vector<std::string> all_keys(std::span<const CaseResult> cases)
{
  std::vector<std::string> keys;
  for (const auto& c : cases)
    for (const auto& [key, value] : c.metrics.items())
      if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
  for (const auto& criterion : ranking_criteria())
    if (std::find(keys.begin(), keys.end(), criterion.key) == keys.end()) keys.push_back(criterion.key);
  return keys;
}

std::string csv_field(const std::string& s)
{
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char ch : s) out += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return out + "\"";
}

std::string full(std::optional<double> v)
{
  return v ? exact_value(*v) : "missing";
}
std::string shown(std::optional<double> v)
{
  return v ? format_value(*v) : "missing";
}

} // namespace

Ranking rank_cases(std::span<const CaseResult> cases)
{
  const auto& criteria = ranking_criteria();
  Ranking r;
  r.used.assign(criteria.size(), true);
  r.rows.resize(cases.size());
  for (std::size_t i = 0; i < cases.size(); ++i) r.rows[i].name = cases[i].name;
  for (std::size_t k = 0; k < criteria.size(); ++k) {
    std::vector<std::string> missing;
    std::vector<double> values;
    for (const auto& c : cases) {
      const auto v = metric_value(c, criteria[k].key);
      if (!v) missing.push_back(c.name);
      values.push_back(v.value_or(0.0));
    }
    if (!missing.empty() || cases.empty()) {
      r.used[k] = false;
      std::string who;
      for (const auto& m : missing) who += (who.empty() ? "" : ", ") + m;
      r.left_out.push_back(criteria[k].key + " (missing for: " + who + ")");
      for (auto& row : r.rows) row.scores.push_back(std::nullopt);
      continue;
    }
    const double lo = *std::min_element(values.begin(), values.end());
    const double hi = *std::max_element(values.begin(), values.end());
    for (std::size_t i = 0; i < cases.size(); ++i) {
      double score = 1.0;
      if (hi - lo > tie_tolerance * std::max(std::abs(hi), std::abs(lo)))
        score = criteria[k].higher_is_better ? (values[i] - lo) / (hi - lo) : (hi - values[i]) / (hi - lo);
      r.rows[i].scores.push_back(score);
      r.rows[i].total += score;
    }
  }
  std::vector<std::size_t> order(cases.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return r.rows[a].total > r.rows[b].total; });
  for (std::size_t position = 0; position < order.size(); ++position) {
    // Equal totals share a rank.
    const std::size_t i = order[position];
    r.rows[i].rank = position > 0 && r.rows[order[position - 1]].total == r.rows[i].total
                         ? r.rows[order[position - 1]].rank
                         : static_cast<int>(position) + 1;
  }
  return r;
}

namespace {

/// What the comparison templates fill in (the names templates/comparison.md.tpl lists).
kainjow::mustache::data comparison_values(std::span<const CaseResult> cases,
                                          std::span<const std::string> keys, const Ranking& ranking,
                                          std::span<const fs::path> plots)
{
  using kainjow::mustache::data;
  data values;
  values.set("count", fmt::format("{}", cases.size()));
  data case_rows{data::type::list};
  for (const auto& c : cases) case_rows.push_back(data("name", c.name));
  values.set("cases", case_rows);

  data metric_rows{data::type::list};
  for (const auto& key : keys) {
    data row;
    const std::string symbol = first_text(cases, key, "symbol");
    row.set("key", key);
    row.set("symbol", symbol);
    row.set("label", symbol.empty() ? key : fmt::format("{} (`{}`)", symbol, key));
    row.set("unit", first_text(cases, key, "unit"));
    data cells{data::type::list};
    for (const auto& c : cases) {
      const auto v = metric_value(c, key);
      data cell;
      cell.set("value", shown(v));
      cell.set("exact", v ? exact_value(*v) : std::string("null"));
      cell.set("missing", !v.has_value());
      cells.push_back(cell);
    }
    row.set("values", cells);
    metric_rows.push_back(row);
  }
  values.set("metrics", metric_rows);

  const auto used = std::count(ranking.used.begin(), ranking.used.end(), true);
  values.set("left_out_note", ranking.left_out.empty()
                                  ? std::string("all 12 criteria are ranked")
                                  : fmt::format("{} of 12 criteria ranked; left out as missing: {}", used,
                                                fmt::join(ranking.left_out, "; ")));
  data criterion_rows{data::type::list};
  for (const auto& criterion : ranking_criteria()) {
    data row;
    row.set("key", criterion.key);
    row.set("label", criterion.label);
    row.set("higher_is_better", criterion.higher_is_better);
    criterion_rows.push_back(row);
  }
  values.set("criteria", criterion_rows);
  values.set("plots", plot_template_rows(plots, comparison_plots));
  data ranking_rows{data::type::list};
  for (const auto& r : ranking.rows) {
    data row;
    row.set("name", r.name);
    data scores{data::type::list};
    for (const auto& score : r.scores) {
      data cell;
      cell.set("value", shown(score));
      cell.set("missing", !score.has_value());
      scores.push_back(cell);
    }
    row.set("scores", scores);
    row.set("total", format_value(r.total));
    row.set("rank", fmt::format("{}", r.rank));
    ranking_rows.push_back(row);
  }
  values.set("ranking", ranking_rows);
  return values;
}

} // namespace

ComparisonFiles write_comparison(std::span<const CaseResult> cases, const fs::path& output_directory,
                                 const ComparisonOptions& options)
{
  // The templates first: a user's template that does not parse stops the comparison before it writes.
  const PageTemplates templates = load_page_templates("comparison", options.templates, "--templates");
  const auto keys = all_keys(cases);
  const auto& criteria = ranking_criteria();
  const Ranking ranking = rank_cases(cases);

  std::string metrics_csv = "metric,symbol,unit";
  for (const auto& c : cases) metrics_csv += "," + csv_field(c.name);
  metrics_csv += "\n";
  for (const auto& key : keys) {
    metrics_csv += fmt::format("{},{},{}", key, csv_field(first_text(cases, key, "symbol")),
                               csv_field(first_text(cases, key, "unit")));
    for (const auto& c : cases) metrics_csv += "," + full(metric_value(c, key));
    metrics_csv += "\n";
  }
  std::string ranking_csv = "case";
  for (const auto& criterion : criteria) ranking_csv += "," + criterion.key;
  ranking_csv += ",total,rank\n";
  for (const auto& row : ranking.rows) {
    ranking_csv += csv_field(row.name);
    for (const auto& s : row.scores) ranking_csv += "," + (s ? exact_value(*s) : std::string("missing"));
    ranking_csv += fmt::format(",{},{}\n", exact_value(row.total), row.rank);
  }

  fs::create_directories(output_directory);
  ComparisonFiles files{output_directory / "comparison.md",
                        output_directory / "metrics.csv",
                        output_directory / "ranking.csv",
                        output_directory / "comparison.html",
                        {}};
  // The cases' series and cycles for the plotting script.
  const fs::path curves_file = output_directory / "curves.json";
  if (options.plots) {
    Json curves{{"cases", Json::array()}};
    for (const auto& c : cases)
      curves["cases"].push_back({{"name", c.name},
                                 {"series", fs::absolute(c.run_directory / "timeseries.csv").string()},
                                 {"cycle_start", c.cycle_start ? Json(*c.cycle_start) : Json()},
                                 {"cycle_end", c.cycle_end ? Json(*c.cycle_end) : Json()}});
    io::write_file_atomically(curves_file, curves.dump(2, ' ', false, Json::error_handler_t::replace) + "\n");
  }
  DrawnPlots drawn =
      draw_plots(options.plots, options.python,
                 {"--compare", fs::absolute(curves_file).string(), fs::absolute(output_directory).string()},
                 output_directory, comparison_plots);
  files.plots = std::move(drawn.files);
  const kainjow::mustache::data values = comparison_values(cases, keys, ranking, files.plots);
  const std::string markdown = templates.markdown.render(values), html = templates.html.render(values);
  io::write_file_atomically(files.markdown, markdown);
  io::write_file_atomically(files.metrics_csv, metrics_csv);
  io::write_file_atomically(files.ranking_csv, ranking_csv);
  io::write_file_atomically(files.html, html);
  if (!drawn.problem.empty()) throw RunError(drawn.problem);
  return files;
}

} // namespace ibvalve::hemodynamics
