#include "hemodynamics/compare.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "base/errors.hpp"
#include "hemodynamics/report.hpp"
#include "io/files.hpp"
#include "io/recorded_config.hpp"

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
    for (const io::RecordedEntry& entry : io::read_recorded_config(config))
      c.inputs.emplace_back(entry.key, entry.unit.empty() ? entry.value : entry.value + " " + entry.unit);
  }
  const fs::path stored = run_directory / "report" / "metrics.json";
  Json doc;
  if (fs::exists(stored)) {
    try {
      doc = Json::parse(io::read_text_file(stored));
    } catch (const Json::exception& error) {
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

void distinguish_case_names(std::span<CaseResult> cases)
{
  for (std::size_t i = 0; i < cases.size(); ++i)
    for (std::size_t j = i + 1; j < cases.size(); ++j)
      if (cases[i].name == cases[j].name) {
        for (auto& c : cases)
          c.name += " (" + fs::absolute(c.run_directory).lexically_normal().filename().string() + ")";
        return;
      }
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

} // namespace

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

namespace {

/// The metric's standard uncertainty, 0 when it carries none. A negative or non-finite one is bad input.
double metric_uncertainty(const CaseResult& c, const std::string& key)
{
  const Json* u = metric_field(c, key, "uncertainty");
  if (!u || u->is_null()) return 0.0;
  if (!u->is_number() || !std::isfinite(u->get<double>()) || u->get<double>() < 0.0)
    throw InputError(fmt::format("{}: metric {}: \"uncertainty\" must be a number >= 0, not {}",
                                 (c.run_directory / "report" / "metrics.json").string(), key, u->dump()));
  return u->get<double>();
}

/// The signed shifts of the metric's sources common to the cases ("uncertainty_shared"), by source.
std::map<std::string, double> metric_shared_shifts(const CaseResult& c, const std::string& key)
{
  std::map<std::string, double> shifts;
  const Json* shared = metric_field(c, key, "uncertainty_shared");
  if (!shared || shared->is_null()) return shifts;
  if (!shared->is_object())
    throw InputError(
        fmt::format("{}: metric {}: \"uncertainty_shared\" must be an object of signed shifts, not {}",
                    (c.run_directory / "report" / "metrics.json").string(), key, shared->dump()));
  for (const auto& [name, value] : shared->items()) {
    if (!value.is_number() || !std::isfinite(value.get<double>()))
      throw InputError(fmt::format("{}: metric {}: uncertainty_shared.{} must be a finite number, not {}",
                                   (c.run_directory / "report" / "metrics.json").string(), key, name,
                                   value.dump()));
    shifts[name] = value.get<double>();
  }
  return shifts;
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

std::string full(std::optional<double> v)
{
  return v ? exact_value(*v) : "missing";
}
std::string shown(std::optional<double> v)
{
  return v ? format_value(*v) : "missing";
}

} // namespace

namespace {

/// Min-max scores of one criterion (best 1, worst 0); all 1 when the spread is within tie_tolerance.
std::vector<double> scaled(const std::vector<double>& values, bool higher_is_better)
{
  const double lo = *std::min_element(values.begin(), values.end());
  const double hi = *std::max_element(values.begin(), values.end());
  std::vector<double> scores(values.size(), 1.0);
  if (hi - lo > tie_tolerance * std::max(std::abs(hi), std::abs(lo)))
    for (std::size_t i = 0; i < values.size(); ++i)
      scores[i] = higher_is_better ? (values[i] - lo) / (hi - lo) : (hi - values[i]) / (hi - lo);
  return scores;
}

/// One case's value of a criterion and its standard uncertainty, split into the part of its own
/// (independent) sources and the signed shifts of the sources common to the cases.
struct UncertainValue {
  double value = 0.0;
  double independent = 0.0;
  std::map<std::string, double> shared;
};

/// The standard uncertainty of the difference a - b: the independent parts add in quadrature, and a
/// source common to both contributes the change it makes to the difference, shift_a - shift_b (a
/// source that moves both cases alike leaves their difference as it is).
double difference_uncertainty(const UncertainValue& a, const UncertainValue& b)
{
  double sum = a.independent * a.independent + b.independent * b.independent;
  auto shift = [](const UncertainValue& v, const std::string& name) {
    const auto it = v.shared.find(name);
    return it == v.shared.end() ? 0.0 : it->second;
  };
  for (const auto& [name, unused] : a.shared) sum += std::pow(shift(a, name) - shift(b, name), 2);
  for (const auto& [name, unused] : b.shared)
    if (!a.shared.contains(name)) sum += std::pow(shift(b, name), 2);
  return std::sqrt(sum);
}

/// The values with each chain of indistinguishable ones (sorted neighbours whose difference is within
/// tie_coverage of its standard uncertainty) replaced by the chain's mean.
std::vector<double> tied(const std::vector<UncertainValue>& uncertain)
{
  std::vector<double> values;
  for (const auto& v : uncertain) values.push_back(v.value);
  std::vector<std::size_t> order(values.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) { return values[a] < values[b]; });
  std::vector<double> out(values);
  for (std::size_t first = 0; first < order.size();) {
    std::size_t last = first;
    while (last + 1 < order.size() &&
           values[order[last + 1]] - values[order[last]] <=
               tie_coverage * difference_uncertainty(uncertain[order[last + 1]], uncertain[order[last]]))
      ++last;
    double mean = 0.0;
    for (std::size_t p = first; p <= last; ++p) mean += values[order[p]];
    mean /= static_cast<double>(last - first + 1);
    for (std::size_t p = first; p <= last; ++p) out[order[p]] = mean;
    first = last + 1;
  }
  return out;
}

/// Ranks by total, largest first; equal totals share a rank.
std::vector<int> ranks_of(const std::vector<double>& totals)
{
  std::vector<std::size_t> order(totals.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) { return totals[a] > totals[b]; });
  std::vector<int> ranks(totals.size());
  for (std::size_t position = 0; position < order.size(); ++position) {
    const std::size_t i = order[position];
    ranks[i] = position > 0 && totals[order[position - 1]] == totals[i] ? ranks[order[position - 1]]
                                                                        : static_cast<int>(position) + 1;
  }
  return ranks;
}

/// The ranking's stability, into r.rows[].rank_held and r.order_held: every uncertain value drawn about
/// itself, the cases scored and ranked as if the draw were exact. A rank shared by m tied cases claims no
/// order among them: a case keeps it when its drawn rank is any of its m places. A source common to the
/// cases is one draw z_s per ranking, every case and criterion moved by z_s times its own shift.
void estimate_rank_stability(const std::vector<std::vector<UncertainValue>>& values,
                             const std::vector<std::size_t>& used, const std::vector<int>& ranks, Ranking& r)
{
  const auto& criteria = ranking_criteria();
  const std::size_t n = ranks.size();
  std::vector<std::string> shared_sources;
  for (const std::size_t k : used)
    for (const auto& v : values[k])
      for (const auto& [name, shift] : v.shared)
        if (std::find(shared_sources.begin(), shared_sources.end(), name) == shared_sources.end())
          shared_sources.push_back(name);
  std::vector<int> sharing(n, 0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) sharing[i] += ranks[j] == ranks[i] ? 1 : 0;
  std::mt19937_64 generator(20261205);
  std::normal_distribution<double> normal;
  std::vector<long> held(n, 0);
  long order_held = 0;
  std::map<std::string, double> z;
  for (int draw = 0; draw < rank_stability_draws; ++draw) {
    for (const auto& name : shared_sources) z[name] = normal(generator);
    std::vector<double> drawn_totals(n, 0.0);
    for (const std::size_t k : used) {
      std::vector<double> drawn(n);
      for (std::size_t i = 0; i < n; ++i) {
        const UncertainValue& v = values[k][i];
        drawn[i] = v.value + v.independent * normal(generator);
        for (const auto& [name, shift] : v.shared) drawn[i] += z[name] * shift;
      }
      const std::vector<double> scores = scaled(drawn, criteria[k].higher_is_better);
      for (std::size_t i = 0; i < n; ++i) drawn_totals[i] += scores[i];
    }
    const std::vector<int> drawn_ranks = ranks_of(drawn_totals);
    bool all = true;
    for (std::size_t i = 0; i < n; ++i) {
      const bool same = drawn_ranks[i] >= ranks[i] && drawn_ranks[i] < ranks[i] + sharing[i];
      held[i] += same ? 1 : 0;
      all = all && same;
    }
    order_held += all ? 1 : 0;
  }
  for (std::size_t i = 0; i < n; ++i)
    r.rows[i].rank_held = static_cast<double>(held[i]) / rank_stability_draws;
  r.order_held = static_cast<double>(order_held) / rank_stability_draws;
}

} // namespace

std::string check_criteria(std::span<const std::string> keys)
{
  std::vector<std::string> names;
  for (const auto& criterion : ranking_criteria()) names.push_back(criterion.key);
  for (const auto& key : keys)
    if (std::find(names.begin(), names.end(), key) == names.end())
      return fmt::format("'{}' is no ranking criterion ({})", key, fmt::join(names, ", "));
  return {};
}

Ranking rank_cases(std::span<const CaseResult> cases, std::span<const std::string> leave_out)
{
  if (const std::string why = check_criteria(leave_out); !why.empty()) throw std::invalid_argument(why);
  const auto& criteria = ranking_criteria();
  Ranking r;
  r.used.assign(criteria.size(), true);
  r.rows.resize(cases.size());
  for (std::size_t i = 0; i < cases.size(); ++i) r.rows[i].name = cases[i].name;
  // Per used criterion: the cases' values and standard uncertainties.
  std::vector<std::size_t> used;
  std::vector<std::vector<UncertainValue>> values(criteria.size());
  auto leave = [&](std::size_t k, const std::string& why) {
    r.used[k] = false;
    r.left_out.push_back(fmt::format("{} ({})", criteria[k].key, why));
    for (auto& row : r.rows) row.scores.push_back(std::nullopt);
  };
  for (std::size_t k = 0; k < criteria.size(); ++k) {
    if (std::find(leave_out.begin(), leave_out.end(), criteria[k].key) != leave_out.end()) {
      leave(k, "left out on request");
      continue;
    }
    std::vector<std::string> missing;
    for (const auto& c : cases) {
      const auto v = metric_value(c, criteria[k].key);
      if (!v) missing.push_back(c.name);
      UncertainValue value{v.value_or(0.0), 0.0, {}};
      if (v) {
        // What the shared shifts do not account for is the case's own.
        const double u = metric_uncertainty(c, criteria[k].key);
        value.shared = metric_shared_shifts(c, criteria[k].key);
        double own = u * u;
        for (const auto& [name, shift] : value.shared) own -= shift * shift;
        value.independent = std::sqrt(std::max(own, 0.0));
        r.uncertain = r.uncertain || u > 0.0;
      }
      values[k].push_back(std::move(value));
    }
    if (!missing.empty() || cases.empty()) {
      leave(k, fmt::format("missing for: {}", fmt::join(missing, ", ")));
      continue;
    }
    used.push_back(k);
    const std::vector<double> scores = scaled(tied(values[k]), criteria[k].higher_is_better);
    for (std::size_t i = 0; i < cases.size(); ++i) {
      r.rows[i].scores.push_back(scores[i]);
      r.rows[i].total += scores[i];
    }
  }
  std::vector<double> totals;
  for (const auto& row : r.rows) totals.push_back(row.total);
  const std::vector<int> ranks = ranks_of(totals);
  for (std::size_t i = 0; i < cases.size(); ++i) r.rows[i].rank = ranks[i];
  r.by_rank.resize(cases.size());
  std::iota(r.by_rank.begin(), r.by_rank.end(), 0);
  std::stable_sort(r.by_rank.begin(), r.by_rank.end(), [&](auto a, auto b) { return ranks[a] < ranks[b]; });
  if (!r.uncertain) return r;

  estimate_rank_stability(values, used, ranks, r);
  return r;
}

std::vector<std::string> criterion_notes(std::span<const CaseResult> cases, const Ranking& ranking)
{
  std::vector<std::string> notes;
  const auto& criteria = ranking_criteria();
  for (std::size_t k = 0; k < criteria.size(); ++k) {
    std::vector<std::string> synthetic;
    std::string what;
    for (const auto& c : cases) {
      const Json* flag = metric_field(c, criteria[k].key, "synthetic_data");
      if (!flag || !flag->is_boolean() || !flag->get<bool>()) continue;
      synthetic.push_back(c.name);
      if (what.empty()) what = metric_text(c, criteria[k].key, "note");
    }
    if (synthetic.empty()) continue;
    notes.push_back(
        fmt::format("{}: measured against synthetic data for {} ({}); {}", criteria[k].label,
                    fmt::join(synthetic, ", "), what.empty() ? "the data were generated, not measured" : what,
                    k < ranking.used.size() && ranking.used[k]
                        ? fmt::format("leave it out of the ranking with --leave-out {} (a study: leave_out)",
                                      criteria[k].key)
                        : std::string("it is left out of this ranking")));
  }
  return notes;
}

std::vector<std::pair<std::string, std::vector<std::string>>>
differing_inputs(std::span<const CaseResult> cases)
{
  auto shown = [](const std::string& key) {
    if (key == "name") return false; // the cases' names head the columns
    for (const char* table : {"output.", "log.", "run.", "checkpoint."})
      if (key.rfind(table, 0) == 0) return false;
    return true;
  };
  std::vector<std::string> keys;
  for (const auto& c : cases)
    for (const auto& [key, value] : c.inputs)
      if (shown(key) && std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
  std::vector<std::pair<std::string, std::vector<std::string>>> out;
  for (const auto& key : keys) {
    std::vector<std::string> values;
    for (const auto& c : cases) {
      const auto it =
          std::find_if(c.inputs.begin(), c.inputs.end(), [&](const auto& e) { return e.first == key; });
      values.push_back(it == c.inputs.end() ? (c.inputs.empty() ? "(no config.toml)" : "(unset)")
                                            : it->second);
    }
    if (std::adjacent_find(values.begin(), values.end(), std::not_equal_to<>()) != values.end())
      out.emplace_back(key, std::move(values));
  }
  return out;
}

namespace {

using kainjow::mustache::data;

data text_rows(std::span<const std::string> texts)
{
  data rows{data::type::list};
  for (const auto& t : texts) rows.push_back(data("text", t));
  return rows;
}

/// `metrics`: one row per metric, a cell per case.
data metric_rows(std::span<const CaseResult> cases, std::span<const std::string> keys)
{
  data rows{data::type::list};
  for (const auto& key : keys) {
    data row;
    const std::string symbol = first_text(cases, key, "symbol");
    row.set("key", key);
    row.set("symbol", symbol);
    row.set("label", symbol.empty() ? key : fmt::format("{} (`{}`)", symbol, key));
    row.set("unit", first_text(cases, key, "unit"));
    bool synthetic = false;
    for (const auto& c : cases)
      if (const Json* flag = metric_field(c, key, "synthetic_data"); flag && flag->is_boolean())
        synthetic = synthetic || flag->get<bool>();
    row.set("synthetic", synthetic);
    data cells{data::type::list};
    for (const auto& c : cases) {
      const auto v = metric_value(c, key);
      data cell;
      const double u = v ? metric_uncertainty(c, key) : 0.0;
      cell.set("value", u > 0.0 ? shown(v) + " ± " + format_value(u) : shown(v));
      cell.set("exact", v ? exact_value(*v) : std::string("null"));
      cell.set("missing", !v.has_value());
      cells.push_back(cell);
    }
    row.set("values", cells);
    rows.push_back(row);
  }
  return rows;
}

/// `ranking`: one row per case, in rank order.
data ranking_rows(const Ranking& ranking)
{
  data rows{data::type::list};
  for (const std::size_t i : ranking.by_rank) {
    const RankingRow& r = ranking.rows[i];
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
    row.set("rank_held", fmt::format("{:.0f} %", 100.0 * r.rank_held));
    rows.push_back(row);
  }
  return rows;
}

/// `differences`: one row per differing input, a cell per case.
data difference_rows(std::span<const CaseResult> cases)
{
  data rows{data::type::list};
  for (const auto& [key, values] : differing_inputs(cases)) {
    data row;
    row.set("key", key);
    data cells{data::type::list};
    for (const auto& v : values) cells.push_back(data("value", v));
    row.set("values", cells);
    rows.push_back(row);
  }
  return rows;
}

/// What the comparison templates fill in (the names templates/comparison.md.tpl lists).
data comparison_values(std::span<const CaseResult> cases, std::span<const std::string> keys,
                       const Ranking& ranking, std::span<const fs::path> plots)
{
  data values;
  values.set("count", fmt::format("{}", cases.size()));
  data case_rows{data::type::list};
  for (const auto& c : cases) case_rows.push_back(data("name", c.name));
  values.set("cases", case_rows);
  const data differences = difference_rows(cases);
  values.set("has_differences", !differences.list_value().empty());
  values.set("differences", differences);
  values.set("metrics", metric_rows(cases, keys));
  const auto used = std::count(ranking.used.begin(), ranking.used.end(), true);
  values.set("left_out_note", ranking.left_out.empty()
                                  ? std::string("all 12 criteria are ranked")
                                  : fmt::format("{} of 12 criteria ranked; left out: {}", used,
                                                fmt::join(ranking.left_out, "; ")));
  values.set("criterion_notes", text_rows(criterion_notes(cases, ranking)));
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
  values.set("ranking", ranking_rows(ranking));
  values.set("uncertain", ranking.uncertain);
  values.set(
      "uncertainty_note",
      ranking.uncertain
          ? fmt::format("Values within {:g} combined standard uncertainties of each other tie (the ± "
                        "figures above); with every uncertain metric drawn about its value {} times, "
                        "the whole order holds in {:.0f} % of the draws, each case's rank as its column "
                        "says",
                        tie_coverage, rank_stability_draws, 100.0 * ranking.order_held)
          : std::string("No ranked metric carries an uncertainty: every difference counts, however "
                        "small against the numerical error"));
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
  if (const std::string why = check_criteria(options.leave_out); !why.empty())
    throw InputError("leave out " + why);
  const Ranking ranking = rank_cases(cases, options.leave_out);

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
  ranking_csv += ranking.uncertain ? ",total,rank,rank_held\n" : ",total,rank\n";
  for (const std::size_t i : ranking.by_rank) {
    const RankingRow& row = ranking.rows[i];
    ranking_csv += csv_field(row.name);
    for (const auto& s : row.scores) ranking_csv += "," + (s ? exact_value(*s) : std::string("missing"));
    ranking_csv += fmt::format(",{},{}", exact_value(row.total), row.rank);
    ranking_csv += ranking.uncertain ? fmt::format(",{}\n", exact_value(row.rank_held)) : "\n";
  }

  io::create_output_folder(output_directory);
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
