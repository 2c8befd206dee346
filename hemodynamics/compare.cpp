#include "hemodynamics/compare.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

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
      if (hi > lo)
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

ComparisonFiles write_comparison(std::span<const CaseResult> cases, const fs::path& output_directory)
{
  const auto keys = all_keys(cases);
  const auto& criteria = ranking_criteria();
  const Ranking ranking = rank_cases(cases);
  auto unit_of = [&](const std::string& key) {
    for (const auto& c : cases)
      if (auto u = metric_text(c, key, "unit"); !u.empty()) return u;
    return std::string();
  };
  auto symbol_of = [&](const std::string& key) {
    for (const auto& c : cases)
      if (auto s = metric_text(c, key, "symbol"); !s.empty()) return s;
    return std::string();
  };
  const std::size_t used_count =
      static_cast<std::size_t>(std::count(ranking.used.begin(), ranking.used.end(), true));
  const std::string left_out_text =
      ranking.left_out.empty() ? std::string("all 12 criteria are ranked")
                               : std::to_string(used_count) + " of 12 criteria ranked; left out as missing: ";

  // --- CSV
  std::ostringstream metrics_csv, ranking_csv;
  metrics_csv << "metric,symbol,unit";
  for (const auto& c : cases) metrics_csv << "," << csv_field(c.name);
  metrics_csv << "\n";
  for (const auto& key : keys) {
    metrics_csv << key << "," << csv_field(symbol_of(key)) << "," << csv_field(unit_of(key));
    for (const auto& c : cases) metrics_csv << "," << full(metric_value(c, key));
    metrics_csv << "\n";
  }
  ranking_csv << "case";
  for (const auto& criterion : criteria) ranking_csv << "," << criterion.key;
  ranking_csv << ",total,rank\n";
  for (const auto& row : ranking.rows) {
    ranking_csv << csv_field(row.name);
    for (const auto& s : row.scores) ranking_csv << "," << (s ? exact_value(*s) : "missing");
    ranking_csv << "," << exact_value(row.total) << "," << row.rank << "\n";
  }

  // --- Markdown
  std::ostringstream md;
  md << "# ibvalve comparison of " << cases.size()
     << " case(s)\n\n## Metrics per case (Table 7 style)\n\n| metric | unit |";
  for (const auto& c : cases) md << " " << c.name << " |";
  md << "\n|---|---|";
  for (std::size_t i = 0; i < cases.size(); ++i) md << "---|";
  md << "\n";
  for (const auto& key : keys) {
    md << "| " << (symbol_of(key).empty() ? key : symbol_of(key) + " (`" + key + "`)") << " | "
       << unit_of(key) << " |";
    for (const auto& c : cases) md << " " << shown(metric_value(c, key)) << " |";
    md << "\n";
  }
  md << "\n## Ranking (Table 8 style)\n\nEach criterion: best case 1, worst 0, linear in between; total = "
        "sum; "
        "rank by total. "
     << left_out_text;
  for (std::size_t i = 0; i < ranking.left_out.size(); ++i) md << (i ? "; " : "") << ranking.left_out[i];
  md << ".\n\n| case |";
  for (std::size_t k = 0; k < criteria.size(); ++k)
    md << " " << criteria[k].label << (criteria[k].higher_is_better ? " (higher better)" : " (lower better)")
       << " |";
  md << " total | rank |\n|---|";
  for (std::size_t k = 0; k < criteria.size() + 2; ++k) md << "---|";
  md << "\n";
  for (const auto& row : ranking.rows) {
    md << "| " << row.name << " |";
    for (const auto& s : row.scores) md << " " << (s ? format_value(*s) : std::string("missing")) << " |";
    md << " " << format_value(row.total) << " | " << row.rank << " |\n";
  }

  // --- HTML
  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>ibvalve "
       "comparison</title>\n"
       "<style>body{font-family:sans-serif;margin:2em}table{border-collapse:collapse;margin:1em 0}"
       "td,th{border:1px solid #bbb;padding:3px 8px}td.value{text-align:right}.missing{color:#999}</style>\n"
       "</head>\n<body>\n<h1>ibvalve comparison of "
    << cases.size()
    << " case(s)</h1>\n<h2>Metrics per case (Table 7 style)</h2>\n<table "
       "id=\"metrics\">\n<tr><th>metric</th><th>unit</th>";
  for (const auto& c : cases) h << "<th>" << html_escape(c.name) << "</th>";
  h << "</tr>\n";
  for (const auto& key : keys) {
    h << "<tr data-key=\"" << html_escape(key) << "\"><td>" << html_escape(symbol_of(key)) << " (<code>"
      << html_escape(key) << "</code>)</td><td>" << html_escape(unit_of(key)) << "</td>";
    for (const auto& c : cases) {
      const auto v = metric_value(c, key);
      h << "<td class=\"value" << (v ? "" : " missing") << "\" data-value=\""
        << (v ? exact_value(*v) : "null") << "\">" << shown(v) << "</td>";
    }
    h << "</tr>\n";
  }
  h << "</table>\n<h2>Ranking (Table 8 style)</h2>\n<p>Each criterion: best case 1, worst 0, linear in "
       "between; "
       "total = sum; rank by total. "
    << html_escape(left_out_text);
  for (std::size_t i = 0; i < ranking.left_out.size(); ++i)
    h << (i ? "; " : "") << html_escape(ranking.left_out[i]);
  h << ".</p>\n<table id=\"ranking\">\n<tr><th>case</th>";
  for (const auto& criterion : criteria)
    h << "<th>" << html_escape(criterion.label) << (criterion.higher_is_better ? " &uarr;" : " &darr;")
      << "</th>";
  h << "<th>total</th><th>rank</th></tr>\n";
  for (const auto& row : ranking.rows) {
    h << "<tr><td>" << html_escape(row.name) << "</td>";
    for (const auto& s : row.scores)
      h << "<td class=\"value" << (s ? "" : " missing") << "\">"
        << (s ? format_value(*s) : std::string("missing")) << "</td>";
    h << "<td class=\"value\">" << format_value(row.total) << "</td><td class=\"value\">" << row.rank
      << "</td></tr>\n";
  }
  h << "</table>\n</body>\n</html>\n";

  fs::create_directories(output_directory);
  ComparisonFiles files{output_directory / "comparison.md", output_directory / "metrics.csv",
                        output_directory / "ranking.csv", output_directory / "comparison.html"};
  io::write_file_atomically(files.markdown, md.str());
  io::write_file_atomically(files.metrics_csv, metrics_csv.str());
  io::write_file_atomically(files.ranking_csv, ranking_csv.str());
  io::write_file_atomically(files.html, h.str());
  return files;
}

} // namespace ibvalve::hemodynamics
