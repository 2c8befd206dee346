// Reports and comparisons: exact numbers, the report files of a synthetic run (HTML that references
// existing PNGs and shows metrics.json's values), extra metrics, the templates (standalone lines, a
// user's own, a broken one refused), and the scaled ranking.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <numbers>
#include <regex>

#include <gtest/gtest.h>

#include "base/errors.hpp"
#include "hemodynamics/compare.hpp"
#include "hemodynamics/plotting.hpp"
#include "hemodynamics/report.hpp"
#include "hemodynamics/report_layout.hpp"
#include "hemodynamics/text_template.hpp"
#include "io/files.hpp"

namespace hd = ibvalve::hemodynamics;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name)
{
  const auto dir = fs::temp_directory_path() / ("ibvalve_test_report_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// A run folder with a smooth synthetic cycle (forward and backward half-sine lobes, an orifice area).
void write_run(const fs::path& dir, double forward_amplitude)
{
  std::ofstream out(dir / "timeseries.csv");
  out << std::setprecision(15) << "t,Q_valve,Q_outlet,P_LV,P_Ao,P_Wk,P_nlv,P_nao,orifice_area\n";
  const double pi = std::numbers::pi;
  for (int i = 0; i <= 3200; ++i) {
    const double t = i * 0.8 / 1600, tau = std::fmod(t, 0.8);
    double q = -3.0 * std::sin(pi * tau / 0.1), a = 0.02;
    if (tau >= 0.1 && tau < 0.4) {
      q = forward_amplitude * std::sin(pi * (tau - 0.1) / 0.3);
      a = 0.02 + 3.0 * std::sin(pi * (tau - 0.1) / 0.3);
    } else if (tau >= 0.4) {
      q = -40.0 * std::sin(pi * (tau - 0.4) / 0.4) * std::exp(-20 * (tau - 0.4));
    }
    const double p_ao = 80 + 10 * std::sin(2 * pi * t / 0.8);
    out << t << "," << q << "," << q << "," << p_ao + 0.01 * q << "," << p_ao << "," << p_ao - 1 << ","
        << p_ao + 0.01 * q << "," << p_ao << "," << a << "\n";
  }
}

/// A run folder of `cycles` cycles of the same shape, cycle k's forward lobe (1 + 0.1 (k - 1)) x
/// `forward_amplitude` mL/s, an orifice opening to about `largest_area` cm^2 and a Windkessel
/// pressure that drifts by `drift` mmHg over each cycle.
void write_cycles(const fs::path& dir, int cycles, double forward_amplitude, double largest_area,
                  double drift)
{
  std::ofstream out(dir / "timeseries.csv");
  out << std::setprecision(15) << "t,Q_valve,Q_outlet,P_LV,P_Ao,P_Wk,P_nlv,P_nao,orifice_area\n";
  const double pi = std::numbers::pi;
  for (int i = 0; i <= 1600 * cycles; ++i) {
    const double t = i * 0.8 / 1600, tau = std::fmod(t, 0.8);
    const double amplitude = forward_amplitude * (1.0 + 0.1 * std::min(i / 1600, cycles - 1));
    double q = -3.0 * std::sin(pi * tau / 0.1), a = 0.02;
    if (tau >= 0.1 && tau < 0.4) {
      q = amplitude * std::sin(pi * (tau - 0.1) / 0.3);
      a = 0.02 + largest_area * std::sin(pi * (tau - 0.1) / 0.3);
    } else if (tau >= 0.4) {
      q = -40.0 * std::sin(pi * (tau - 0.4) / 0.4) * std::exp(-20 * (tau - 0.4));
    }
    const double p_ao = 80 + 10 * std::sin(2 * pi * t / 0.8);
    out << t << "," << q << "," << q << "," << p_ao + 0.01 * q << "," << p_ao << ","
        << p_ao - 1 + drift * t / 0.8 << "," << p_ao + 0.01 * q << "," << p_ao << "," << a << "\n";
  }
}

/// A metrics object as metrics.json holds it: key -> {"value": v}.
hd::Json metrics_of(std::initializer_list<std::pair<const char*, double>> values)
{
  hd::Json m = hd::Json::object();
  for (const auto& [key, v] : values) m[key] = hd::Json{{"value", v}, {"unit", ""}, {"symbol", ""}};
  return m;
}

} // namespace

TEST(Report, ExactValuesReadBackAndBase64IsThatOfRfc4648)
{
  EXPECT_EQ(hd::exact_value(0.1), "0.1");
  EXPECT_EQ(std::stod(hd::exact_value(1.0 / 3.0)), 1.0 / 3.0);
  EXPECT_EQ(std::stod(hd::exact_value(-2.5e-300)), -2.5e-300);
  EXPECT_EQ(hd::exact_value(std::nan("")), "null");
  EXPECT_EQ(hd::base64("Man"), "TWFu");
  EXPECT_EQ(hd::base64("Ma"), "TWE=");
  EXPECT_EQ(hd::base64("M"), "TQ==");
}

TEST(Report, HtmlReferencesExistingPngsAndShowsTheMetricsOfTheJson)
{
  const auto run = scratch("run");
  write_run(run, 300.0);
  std::ofstream(run / "extra_metrics.json")
      << R"({"fit_error": {"value": 1.25, "unit": "kPa", "symbol": "MAE"},
    "strain_variation": 0.05})";
  hd::ReportOptions options;
  options.python = IBVALVE_PYTHON;
  const hd::ReportFiles files = hd::write_report(run, options);
  ASSERT_TRUE(fs::exists(files.html));
  ASSERT_TRUE(fs::exists(files.markdown));
  EXPECT_EQ(files.plots.size(), 4u);
  const std::string html = ibvalve::io::read_text_file(files.html);
  // Every referenced PNG exists beside the HTML, and every plot is referenced.
  std::regex href("href=\"([^\"]+\\.png)\"");
  std::set<std::string> referenced;
  for (auto it = std::sregex_iterator(html.begin(), html.end(), href); it != std::sregex_iterator(); ++it) {
    referenced.insert((*it)[1]);
    EXPECT_TRUE(fs::exists(files.directory / (*it)[1].str())) << (*it)[1];
  }
  EXPECT_EQ(referenced.size(), 4u);
  EXPECT_NE(html.find("data:image/png;base64,iVBORw0KGgo"), std::string::npos); // embedded PNG signature
  // The values in the HTML are those of metrics.json.
  const hd::Json doc = hd::Json::parse(ibvalve::io::read_text_file(files.json));
  const hd::Json& metrics = doc.at("metrics");
  std::regex cell("<tr data-key=\"([a-z_]+)\">.*?data-value=\"([^\"]+)\"");
  int compared = 0;
  for (auto it = std::sregex_iterator(html.begin(), html.end(), cell); it != std::sregex_iterator(); ++it) {
    ASSERT_TRUE(metrics.contains((*it)[1].str())) << (*it)[1];
    const hd::Json& v = metrics.at((*it)[1].str()).at("value");
    if ((*it)[2] == "null") {
      EXPECT_TRUE(v.is_null());
    } else {
      EXPECT_EQ(std::stod((*it)[2]), v.get<double>()) << (*it)[1];
    }
    ++compared;
  }
  EXPECT_EQ(static_cast<std::size_t>(compared), metrics.size());
  EXPECT_EQ(metrics.at("fit_error").at("value").get<double>(), 1.25);
  EXPECT_EQ(metrics.at("strain_variation").at("value").get<double>(), 0.05);
  EXPECT_GT(metrics.at("forward_volume").at("value").get<double>(), 0.0);
  fs::remove_all(run);
}

TEST(Report, BadRunFoldersAreInputErrorsBeforeWriting)
{
  const auto run = scratch("bad");
  hd::ReportOptions options;
  options.plots = false;
  EXPECT_THROW(hd::write_report(run, options), ibvalve::InputError); // no timeseries.csv
  std::ofstream(run / "timeseries.csv") << "t,Q_valve,P_LV\n0,1,2\n";
  EXPECT_THROW(hd::write_report(run, options), ibvalve::InputError); // missing columns
  EXPECT_FALSE(fs::exists(run / "report"));
  fs::remove_all(run);
}

TEST(Template, StandaloneTagLinesLeaveNoTraceWhetherTheirSectionIsRenderedOrNot)
{
  const hd::TextTemplate t(
      "{{! a comment\n  over two lines }}\n# {{title}}\n\n{{#rows}}\n- {{text}}\n{{/rows}}\n"
      "{{^rows}}\n(none)\n{{/rows}}\n\n{{empty}}\nend {{#flag}}on{{/flag}}\n",
      "t.tpl", hd::TextTemplate::Escaping::html);
  kainjow::mustache::data values;
  values.set("title", "a < b");
  values.set("empty", "");
  values.set("flag", false);
  kainjow::mustache::data rows{kainjow::mustache::data::type::list};
  for (const char* text : {"one", "two"}) {
    kainjow::mustache::data row;
    row.set("text", text);
    rows.push_back(row);
  }
  values.set("rows", rows);
  EXPECT_EQ(t.render(values), "# a &lt; b\n\n- one\n- two\n\n\nend \n");
  values.set("rows", kainjow::mustache::data{kainjow::mustache::data::type::list});
  EXPECT_EQ(t.render(values), "# a &lt; b\n\n(none)\n\n\nend \n");
}

TEST(Template, ABrokenTemplateIsAnInputErrorNamingFileAndLine)
{
  try {
    hd::TextTemplate("line 1\n{{#rows}}\nno end\n", "mine.tpl", hd::TextTemplate::Escaping::markdown);
    FAIL() << "an unclosed section was accepted";
  } catch (const ibvalve::InputError& error) {
    EXPECT_EQ(std::string(error.what()).rfind("mine.tpl:2: Unclosed section \"rows\"", 0), 0u)
        << error.what();
  }
  EXPECT_THROW(hd::TextTemplate("{{value", "mine.tpl", hd::TextTemplate::Escaping::markdown),
               ibvalve::InputError);
}

TEST(Report, AUsersTemplateLaysOutTheReportAndTheBuiltInOneServesForTheOtherFile)
{
  const auto run = scratch("user_template");
  write_run(run, 300.0);
  const auto templates = scratch("user_template_files");
  const auto written = hd::write_builtin_templates(templates);
  ASSERT_EQ(written.size(), 4u); // the report's and the comparison's
  EXPECT_THROW(hd::write_builtin_templates(templates), ibvalve::InputError); // nothing is overwritten
  std::string html = ibvalve::io::read_text_file(templates / "report.html.tpl");
  html.replace(html.find("<h2>Metrics</h2>"), 16, "<h2>MARKER {{run}}</h2>");
  ibvalve::io::write_file_atomically(templates / "report.html.tpl", html);
  fs::remove(templates / "report.md.tpl");
  hd::ReportOptions options;
  options.plots = false;
  const hd::ReportFiles files = hd::write_report(run, options);
  const std::string builtin_md = ibvalve::io::read_text_file(files.markdown);
  options.templates = templates;
  hd::write_report(run, options);
  EXPECT_NE(ibvalve::io::read_text_file(files.html).find("<h2>MARKER ibvalve_test_report_user_template</h2>"),
            std::string::npos);
  // The same page but for the instant each was written (its provenance's "at ...Z" may tick a second).
  const auto undated = [](const std::string& page) {
    return std::regex_replace(page, std::regex(R"(at \d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ)"), "at (time)");
  };
  EXPECT_EQ(undated(ibvalve::io::read_text_file(files.markdown)), undated(builtin_md));
  fs::remove_all(run);
  fs::remove_all(templates);
}

TEST(Report, ABrokenOrMissingTemplateIsRefusedBeforeAnythingIsWritten)
{
  const auto run = scratch("broken_template");
  write_run(run, 300.0);
  const auto templates = scratch("broken_template_files");
  std::ofstream(templates / "report.md.tpl") << "# {{run}}\n{{#metrics}}\n| {{key}} |\n";
  hd::ReportOptions options;
  options.plots = false;
  options.templates = templates;
  try {
    hd::write_report(run, options);
    FAIL() << "a broken template was accepted";
  } catch (const ibvalve::InputError& error) {
    EXPECT_NE(std::string(error.what()).find((templates / "report.md.tpl").string() + ":2:"),
              std::string::npos)
        << error.what();
  }
  EXPECT_FALSE(fs::exists(run / "report"));
  options.templates = templates / "absent";
  EXPECT_THROW(hd::write_report(run, options), ibvalve::InputError);
  fs::remove(templates / "report.md.tpl");
  options.templates = templates; // a folder holding neither template
  EXPECT_THROW(hd::write_report(run, options), ibvalve::InputError);
  EXPECT_FALSE(fs::exists(run / "report"));
  fs::remove_all(run);
  fs::remove_all(templates);
}

TEST(Compare, ScalesEachCriterionBestToOneWorstToZeroAndLeavesOutMissingOnes)
{
  auto make = [](const std::string& name, double vf, double rf, std::optional<double> fit) {
    hd::CaseResult c;
    c.name = name;
    auto entry = [](std::optional<double> v) {
      return hd::Json{{"value", v ? hd::Json(*v) : hd::Json()}, {"unit", ""}, {"symbol", ""}};
    };
    c.metrics = hd::Json{
        {"forward_volume", entry(vf)}, {"regurgitant_fraction", entry(rf)}, {"fit_error", entry(fit)}};
    return c;
  };
  std::vector<hd::CaseResult> cases{make("a", 60, 10, 1.0), make("b", 80, 5, std::nullopt),
                                    make("c", 70, 20, 2.0)};
  const hd::Ranking r = hd::rank_cases(cases);
  const auto& criteria = hd::ranking_criteria();
  ASSERT_EQ(criteria.size(), 12u);
  auto index = [&](const std::string& key) {
    for (std::size_t k = 0; k < criteria.size(); ++k)
      if (criteria[k].key == key) return k;
    return criteria.size();
  };
  const std::size_t vf = index("forward_volume"), rf = index("regurgitant_fraction"),
                    fit = index("fit_error");
  EXPECT_TRUE(r.used[vf]);
  EXPECT_TRUE(r.used[rf]);
  EXPECT_FALSE(r.used[fit]); // missing for b
  EXPECT_EQ(r.left_out.size(), 10u);
  EXPECT_DOUBLE_EQ(*r.rows[0].scores[vf], 0.0); // 60: worst (higher is better)
  EXPECT_DOUBLE_EQ(*r.rows[1].scores[vf], 1.0);
  EXPECT_DOUBLE_EQ(*r.rows[2].scores[vf], 0.5);
  EXPECT_DOUBLE_EQ(*r.rows[0].scores[rf], 10.0 / 15.0); // (20 - 10) / (20 - 5), lower is better
  EXPECT_DOUBLE_EQ(*r.rows[1].scores[rf], 1.0);
  EXPECT_DOUBLE_EQ(*r.rows[2].scores[rf], 0.0);
  EXPECT_EQ(r.rows[1].rank, 1);
  EXPECT_EQ(r.rows[2].rank, 3);
  EXPECT_EQ(r.rows[0].rank, 2);
  const auto out = scratch("compare");
  hd::ComparisonOptions pages_only;
  pages_only.plots = false; // these cases have metrics but no time series to draw
  const auto files = hd::write_comparison(cases, out, pages_only);
  const std::string md = ibvalve::io::read_text_file(files.markdown);
  EXPECT_NE(md.find("fit_error (missing for: b)"), std::string::npos);
  EXPECT_NE(ibvalve::io::read_text_file(files.ranking_csv).find("b,missing,missing"), std::string::npos);
  EXPECT_TRUE(fs::exists(files.html));
  fs::remove_all(out);
}

TEST(Report, NamesInTheMarkdownPagesCannotOpenATagOrEndATableCell)
{
  // A run folder (the report's name for the run) and cases named with HTML and a table's bar.
  const auto run = scratch("names") / "<script>a|b";
  fs::create_directories(run);
  write_run(run, 300.0);
  hd::ReportOptions options;
  options.plots = false;
  const std::string report = ibvalve::io::read_text_file(hd::write_report(run, options).markdown);
  EXPECT_NE(report.find("# ibvalve report: &lt;script&gt;a\\|b, cycle 2 of 2\n"), std::string::npos)
      << report.substr(0, 200);
  EXPECT_EQ(report.find("<script>"), std::string::npos);

  auto make = [](const std::string& name, double vf) {
    hd::CaseResult c;
    c.name = name;
    c.metrics = hd::Json{{"forward_volume", hd::Json{{"value", vf}, {"unit", "mL"}, {"symbol", "V_F"}}}};
    return c;
  };
  const std::vector<hd::CaseResult> cases{make("<b>x</b> & y", 60), make("a|b", 80)};
  const auto out = scratch("names_compare");
  hd::ComparisonOptions pages_only;
  pages_only.plots = false;
  const std::string md = ibvalve::io::read_text_file(hd::write_comparison(cases, out, pages_only).markdown);
  EXPECT_NE(md.find("| &lt;b&gt;x&lt;/b&gt; &amp; y | a\\|b |"), std::string::npos) << md.substr(0, 400);
  EXPECT_EQ(md.find("<b>"), std::string::npos);
  // Every row of the metrics table has as many cells as its header.
  const auto header = md.find("| metric | unit |");
  ASSERT_NE(header, std::string::npos);
  const auto cells = [](std::string_view line) {
    std::size_t bars = 0;
    for (std::size_t i = 0; i < line.size(); ++i) bars += line[i] == '|' && (i == 0 || line[i - 1] != '\\');
    return bars;
  };
  const std::string header_line = md.substr(header, md.find('\n', header) - header);
  const auto row = md.find("| V_F");
  ASSERT_NE(row, std::string::npos) << md;
  EXPECT_EQ(cells(md.substr(row, md.find('\n', row) - row)), cells(header_line));
  fs::remove_all(run.parent_path());
  fs::remove_all(out);
}

TEST(Compare, ValuesWithinTheTieToleranceTieAndLargerDifferencesAreScored)
{
  auto make = [](const std::string& name, double vf) {
    hd::CaseResult c;
    c.name = name;
    c.metrics = hd::Json{{"forward_volume", hd::Json{{"value", vf}, {"unit", "mL"}, {"symbol", "V_F"}}}};
    return c;
  };
  const auto& criteria = hd::ranking_criteria();
  std::size_t vf = 0;
  while (criteria[vf].key != "forward_volume") ++vf;
  // 1e-9 apart (round-off): a tie, both score 1 and share the first rank.
  const std::vector<hd::CaseResult> round_off{make("a", 80.0), make("b", 80.0 * (1 + 1e-9))};
  hd::Ranking r = hd::rank_cases(round_off);
  EXPECT_EQ(*r.rows[0].scores[vf], 1.0);
  EXPECT_EQ(*r.rows[1].scores[vf], 1.0);
  EXPECT_EQ(r.rows[0].rank, 1);
  EXPECT_EQ(r.rows[1].rank, 1);
  // Just inside and just outside the stated tolerance.
  r = hd::rank_cases(
      std::vector<hd::CaseResult>{make("a", 80.0), make("b", 80.0 * (1 + 0.9 * hd::tie_tolerance))});
  EXPECT_EQ(*r.rows[0].scores[vf], 1.0);
  r = hd::rank_cases(std::vector<hd::CaseResult>{make("a", 80.0), make("b", 80.0 * (1 + 1e-2))});
  EXPECT_EQ(*r.rows[0].scores[vf], 0.0); // 1 % less forward volume: the worst
  EXPECT_EQ(*r.rows[1].scores[vf], 1.0);
  EXPECT_EQ(r.rows[1].rank, 1);
  EXPECT_EQ(r.rows[0].rank, 2);
}

namespace {

/// A case with forward volume and TPG, each with a standard uncertainty (none when 0).
hd::CaseResult uncertain_case(const std::string& name, double vf, double u_vf, double tpg, double u_tpg)
{
  auto entry = [](double v, double u) {
    hd::Json m{{"value", v}, {"unit", ""}, {"symbol", ""}};
    if (u > 0.0) m["uncertainty"] = u;
    return m;
  };
  hd::CaseResult c;
  c.name = name;
  c.metrics =
      hd::Json{{"forward_volume", entry(vf, u_vf)}, {"transvalvular_pressure_gradient", entry(tpg, u_tpg)}};
  return c;
}

std::size_t criterion_index(const std::string& key)
{
  const auto& criteria = hd::ranking_criteria();
  std::size_t k = 0;
  while (criteria[k].key != key) ++k;
  return k;
}

} // namespace

TEST(Compare, DifferencesWithinTheCombinedUncertaintyTieAndLargerOnesAreScored)
{
  // V_F 80, 81, 90 mL with u = 1 mL each: 80 and 81 differ by 1 <= 2 sqrt(1 + 1) = 2.83, a tie scored
  // as their mean 80.5; 90 is 9 from 81, beyond it. TPG 10 and 10.5 and 20 mmHg with no uncertainty:
  // every difference counts, as before.
  const std::vector<hd::CaseResult> cases{uncertain_case("a", 80, 1, 10, 0),
                                          uncertain_case("b", 81, 1, 10.5, 0),
                                          uncertain_case("c", 90, 1, 20, 0)};
  const hd::Ranking r = hd::rank_cases(cases);
  const std::size_t vf = criterion_index("forward_volume"),
                    tpg = criterion_index("transvalvular_pressure_gradient");
  EXPECT_TRUE(r.uncertain);
  EXPECT_DOUBLE_EQ(*r.rows[0].scores[vf], 0.0);
  EXPECT_DOUBLE_EQ(*r.rows[1].scores[vf], 0.0); // tied with a
  EXPECT_DOUBLE_EQ(*r.rows[2].scores[vf], 1.0);
  EXPECT_DOUBLE_EQ(*r.rows[0].scores[tpg], 1.0);
  EXPECT_DOUBLE_EQ(*r.rows[1].scores[tpg], 0.95); // (20 - 10.5) / 10: not tied, no uncertainty
  // Just beyond the coverage: 80 and 80 + 2.9 (> 2.83) are scored apart.
  const hd::Ranking apart = hd::rank_cases(
      std::vector<hd::CaseResult>{uncertain_case("a", 80, 1, 10, 0), uncertain_case("b", 82.9, 1, 10, 0)});
  EXPECT_DOUBLE_EQ(*apart.rows[0].scores[vf], 0.0);
  EXPECT_DOUBLE_EQ(*apart.rows[1].scores[vf], 1.0);
  const hd::Ranking together = hd::rank_cases(
      std::vector<hd::CaseResult>{uncertain_case("a", 80, 1, 10, 0), uncertain_case("b", 82.8, 1, 10, 0)});
  EXPECT_DOUBLE_EQ(*together.rows[0].scores[vf], 1.0); // one group: all tie at 1
  EXPECT_DOUBLE_EQ(*together.rows[1].scores[vf], 1.0);
  // A negative uncertainty is bad input.
  std::vector<hd::CaseResult> bad{uncertain_case("a", 80, 1, 10, 0), uncertain_case("b", 81, 1, 10, 0)};
  bad[1].metrics["forward_volume"]["uncertainty"] = -1.0;
  EXPECT_THROW(hd::rank_cases(bad), ibvalve::InputError);
}

TEST(Compare, TheRankStabilityIsHowOftenEachCaseKeepsItsRankUnderTheUncertainties)
{
  // Far apart against their uncertainties (V_F 60, 80, 100 mL, u = 1): every draw keeps the order.
  hd::Ranking r = hd::rank_cases(std::vector<hd::CaseResult>{uncertain_case("a", 60, 1, 10, 0),
                                                             uncertain_case("b", 80, 1, 10, 0),
                                                             uncertain_case("c", 100, 1, 10, 0)});
  EXPECT_DOUBLE_EQ(r.order_held, 1.0);
  for (const auto& row : r.rows) EXPECT_DOUBLE_EQ(row.rank_held, 1.0);
  // V_F 80 and 86 mL with u = 1.5 each: 6 > 2 sqrt(1.5^2 + 1.5^2) = 4.24, so b ranks first; a draw
  // reverses them when the drawn difference, normal with mean 6 and standard deviation 2.12, falls
  // below 0: Phi(-2.83) = 0.23 % of draws (binomial standard error 0.05 % at 10,000 draws).
  r = hd::rank_cases(
      std::vector<hd::CaseResult>{uncertain_case("a", 80, 1.5, 10, 0), uncertain_case("b", 86, 1.5, 10, 0)});
  const double flipped = 0.5 * std::erfc(6.0 / std::hypot(1.5, 1.5) / std::sqrt(2.0));
  EXPECT_NEAR(r.order_held, 1.0 - flipped, 0.002);
  EXPECT_LT(r.order_held, 1.0);
  // The same pair 1 mL apart ties (1 <= 4.24): both share rank 1 and claim no order, so every draw
  // keeps it.
  r = hd::rank_cases(
      std::vector<hd::CaseResult>{uncertain_case("a", 80, 1.5, 10, 0), uncertain_case("b", 81, 1.5, 10, 0)});
  EXPECT_EQ(r.rows[0].rank, 1);
  EXPECT_EQ(r.rows[1].rank, 1);
  EXPECT_DOUBLE_EQ(r.order_held, 1.0);
  // Three cases, two of them 3 u apart (ranked), drawn: the first holds its rank less often than the
  // clear last.
  r = hd::rank_cases(std::vector<hd::CaseResult>{uncertain_case("a", 80, 1, 10, 0),
                                                 uncertain_case("b", 84.5, 1, 10, 0),
                                                 uncertain_case("c", 60, 1, 10, 0)});
  EXPECT_EQ(r.rows[1].rank, 1);
  EXPECT_EQ(r.rows[2].rank, 3);
  EXPECT_LT(r.rows[1].rank_held, 1.0);
  EXPECT_DOUBLE_EQ(r.rows[2].rank_held, 1.0);
  // Without uncertainties nothing is drawn: the order "holds" by construction, and the pages say
  // that every difference counts.
  r = hd::rank_cases(
      std::vector<hd::CaseResult>{uncertain_case("a", 80, 0, 10, 0), uncertain_case("b", 81, 0, 10, 0)});
  EXPECT_FALSE(r.uncertain);
  EXPECT_DOUBLE_EQ(r.order_held, 1.0);
  // The pages show the +- figures, the note and the column.
  const std::vector<hd::CaseResult> cases{uncertain_case("a", 80, 2, 10, 1),
                                          uncertain_case("b", 90, 2, 12, 1)};
  const auto out = scratch("compare_uncertain");
  hd::ComparisonOptions pages_only;
  pages_only.plots = false;
  const auto files = hd::write_comparison(cases, out, pages_only);
  const std::string md = ibvalve::io::read_text_file(files.markdown);
  EXPECT_NE(md.find("80 ± 2"), std::string::npos) << md;
  EXPECT_NE(md.find("rank held"), std::string::npos);
  EXPECT_NE(md.find("the whole order holds in"), std::string::npos);
  EXPECT_NE(md.find("2 combined standard uncertainties"), std::string::npos);
  EXPECT_NE(ibvalve::io::read_text_file(files.ranking_csv).find(",total,rank,rank_held"), std::string::npos);
  fs::remove_all(out);
}

TEST(Compare, ASourceCommonToTheCasesJudgesADifferenceByHowMuchItChangesTheDifference)
{
  // V_F 80 and 83 mL, each with u = 5 mL from a second grid. Independent, the 3 mL difference is within
  // 2 sqrt(5^2 + 5^2) = 14.1 and the two tie. Shared, with shifts +5 and +5.5 (the second grid moves
  // both up and the difference by 0.5), the difference's uncertainty is 0.5: 3 > 2 x 0.5, they are
  // scored apart, and a draw reverses them when 3 + 0.5 z < 0, z < -6: never in 10,000 draws.
  auto with_shift = [](hd::CaseResult c, double shift) {
    c.metrics["forward_volume"]["uncertainty_sources"] = hd::Json{{"grid", std::abs(shift)}};
    c.metrics["forward_volume"]["uncertainty_shared"] = hd::Json{{"grid", shift}};
    return c;
  };
  const std::size_t vf = criterion_index("forward_volume");
  const hd::Ranking independent = hd::rank_cases(
      std::vector<hd::CaseResult>{uncertain_case("a", 80, 5, 10, 0), uncertain_case("b", 83, 5, 10, 0)});
  EXPECT_DOUBLE_EQ(*independent.rows[0].scores[vf], 1.0);
  EXPECT_DOUBLE_EQ(*independent.rows[1].scores[vf], 1.0);
  const hd::Ranking shared =
      hd::rank_cases(std::vector<hd::CaseResult>{with_shift(uncertain_case("a", 80, 5, 10, 0), 5.0),
                                                 with_shift(uncertain_case("b", 83, 5.5, 10, 0), 5.5)});
  EXPECT_DOUBLE_EQ(*shared.rows[0].scores[vf], 0.0);
  EXPECT_DOUBLE_EQ(*shared.rows[1].scores[vf], 1.0);
  EXPECT_EQ(shared.rows[1].rank, 1);
  EXPECT_DOUBLE_EQ(shared.order_held, 1.0);
  // Opposite shifts, +5 and -5, change the difference by 10: 3 <= 2 x 10, a tie.
  const hd::Ranking opposite =
      hd::rank_cases(std::vector<hd::CaseResult>{with_shift(uncertain_case("a", 80, 5, 10, 0), 5.0),
                                                 with_shift(uncertain_case("b", 83, 5, 10, 0), -5.0)});
  EXPECT_DOUBLE_EQ(*opposite.rows[0].scores[vf], 1.0);
  EXPECT_DOUBLE_EQ(*opposite.rows[1].scores[vf], 1.0);
  // Apart by 9 mL with shifts +1 and +5 and no own part: the difference's uncertainty is 4 (9 > 2 x 4,
  // scored apart), and a draw reverses the pair when 9 + 4 z < 0, z < -2.25: Phi(-2.25) = 1.22 % of
  // draws (binomial standard error 0.11 %).
  hd::Ranking drawn =
      hd::rank_cases(std::vector<hd::CaseResult>{with_shift(uncertain_case("a", 80, 1, 10, 0), 1.0),
                                                 with_shift(uncertain_case("b", 89, 5, 10, 0), 5.0)});
  EXPECT_EQ(drawn.rows[1].rank, 1);
  EXPECT_NEAR(drawn.order_held, 1.0 - 0.5 * std::erfc(2.25 / std::sqrt(2.0)), 0.004);
  // A case's own part is what its shared shifts leave of u: u = 5 with a shift of 3 leaves 4, which adds
  // in quadrature to the pair's 0 shared change: 3 <= 2 x 4, a tie.
  const hd::Ranking own =
      hd::rank_cases(std::vector<hd::CaseResult>{with_shift(uncertain_case("a", 80, 5, 10, 0), 3.0),
                                                 with_shift(uncertain_case("b", 83, 3, 10, 0), 3.0)});
  EXPECT_DOUBLE_EQ(*own.rows[0].scores[vf], 1.0);
  EXPECT_DOUBLE_EQ(*own.rows[1].scores[vf], 1.0);
  // A shift that is not a finite number is bad input.
  std::vector<hd::CaseResult> bad{with_shift(uncertain_case("a", 80, 5, 10, 0), 5.0),
                                  uncertain_case("b", 83, 5, 10, 0)};
  bad[0].metrics["forward_volume"]["uncertainty_shared"]["grid"] = "up";
  EXPECT_THROW(hd::rank_cases(bad), ibvalve::InputError);
}

TEST(Compare, AUsersTemplateLaysOutTheComparisonAndABrokenOneWritesNothing)
{
  hd::CaseResult one;
  one.name = "one";
  one.metrics = hd::Json{{"forward_volume", hd::Json{{"value", 70.0}, {"unit", "mL"}, {"symbol", "V_F"}}}};
  const std::vector<hd::CaseResult> cases{one};
  const auto templates = scratch("compare_templates");
  hd::write_builtin_templates(templates);
  ibvalve::io::write_file_atomically(
      templates / "comparison.md.tpl",
      "MARKER {{count}}{{#metrics}} {{key}}={{#values}}{{value}}{{/values}}{{/metrics}}\n");
  fs::remove(templates / "comparison.html.tpl");
  const auto out = scratch("compare_user");
  const hd::ComparisonOptions options{templates, "/usr/bin/python3", false, {}};
  const auto files = hd::write_comparison(cases, out, options);
  const std::string md = ibvalve::io::read_text_file(files.markdown);
  EXPECT_EQ(md.rfind("MARKER 1 forward_volume=70", 0), 0u) << md;
  EXPECT_NE(ibvalve::io::read_text_file(files.html).find("<table id=\"ranking\">"), std::string::npos);
  fs::remove_all(out);

  ibvalve::io::write_file_atomically(templates / "comparison.md.tpl", "{{#metrics}}\n");
  try {
    hd::write_comparison(cases, out, options);
    ADD_FAILURE() << "a broken template was accepted";
  } catch (const ibvalve::InputError& error) {
    EXPECT_NE(std::string(error.what()).find("comparison.md.tpl:1:"), std::string::npos) << error.what();
  }
  EXPECT_FALSE(fs::exists(out));
  EXPECT_THROW(hd::write_comparison(cases, out, {templates / "missing", "/usr/bin/python3", false, {}}),
               ibvalve::InputError);
  EXPECT_FALSE(fs::exists(out));
  fs::remove_all(templates);
}

TEST(Report, SettingsComeFromTheRunsConfig)
{
  const auto run = scratch("settings");
  EXPECT_EQ(hd::metric_settings_from_run(run).period, 0.8); // no config.toml: defaults
  std::ofstream(run / "config.toml") << "model = \"lumped\"\n[report]\nperiod = 1\ncycle = 1\n"
                                        "closure_rule = \"area\"\nclosed_area_fraction = 0.02\n";
  const hd::MetricSettings s = hd::metric_settings_from_run(run);
  EXPECT_EQ(s.period, 1.0);
  EXPECT_EQ(s.cycle, 1);
  EXPECT_EQ(s.closure_rule, hd::ClosureRule::area);
  EXPECT_EQ(s.closed_area_fraction, 0.02);
  EXPECT_EQ(s.open_area_fraction, 0.9);
  std::ofstream(run / "config.toml") << "[report]\nperiod = \"long\"\n";
  EXPECT_THROW(hd::metric_settings_from_run(run), ibvalve::InputError);
  std::ofstream(run / "config.toml") << "[report]\ncycle = 0\n"; // cycles count from 1
  EXPECT_THROW(hd::metric_settings_from_run(run), ibvalve::InputError);
  std::ofstream(run / "config.toml") << "[report]\nclosure_rule = \"guess\"\n";
  EXPECT_THROW(hd::metric_settings_from_run(run), ibvalve::InputError);
  fs::remove_all(run);
}

TEST(Report, HeadlineFiguresAreAssessedAgainstTheirPublishedRangesWithTheirSources)
{
  const hd::Json metrics = metrics_of({{"regurgitant_fraction", 29.9},
                                       {"transvalvular_pressure_gradient", 25.0},
                                       {"effective_orifice_area", 1.5},
                                       {"peak_velocity_open", 2.5},
                                       {"forward_volume", 70.0}});
  const hd::Json headline = hd::headline_document(metrics);
  std::vector<std::string> keys;
  for (const hd::Json& h : headline) keys.push_back(h.at("key").get<std::string>());
  EXPECT_EQ(keys, (std::vector<std::string>{"forward_volume", "regurgitant_fraction",
                                            "transvalvular_pressure_gradient", "effective_orifice_area",
                                            "energy_loss", "peak_forward_flow", "max_orifice_area",
                                            "peak_velocity_open"}));
  auto row = [&](const std::string& key) {
    for (const hd::Json& h : headline)
      if (h.at("key") == key) return h;
    return hd::Json();
  };
  EXPECT_EQ(row("regurgitant_fraction").at("assessment"), "within");             // RF < 30 %
  EXPECT_EQ(row("transvalvular_pressure_gradient").at("assessment"), "outside"); // not < 20 mmHg
  EXPECT_EQ(row("effective_orifice_area").at("assessment"), "outside");          // not > 1.5 cm^2
  EXPECT_EQ(row("peak_velocity_open").at("assessment"), "within");               // <= 2.5 m/s
  EXPECT_EQ(row("forward_volume").at("assessment"), "");                         // no published range here
  EXPECT_TRUE(row("energy_loss").at("value").is_null()); // not in the metrics: no value
  EXPECT_EQ(row("transvalvular_pressure_gradient").at("source"), "Baumgartner et al. 2017");
  EXPECT_EQ(row("regurgitant_fraction").at("source"), "Zoghbi et al. 2017");
  // Every range's source has its full citation.
  for (const hd::Json& h : headline) {
    if (h.at("source") == "") continue;
    bool cited = false;
    for (const auto& source : hd::reference_sources()) cited = cited || h.at("source") == source.name;
    EXPECT_TRUE(cited) << h.at("source");
  }
}

TEST(Report, AnEoaAboveTheGeometricOrificeAndACycleThatIsNotPeriodicAreFlagged)
{
  auto checks = [](const hd::Json& metrics) {
    std::vector<std::string> names;
    for (const hd::Json& c : hd::plausibility_checks(metrics))
      names.push_back(c.at("check").get<std::string>());
    return names;
  };
  using names = std::vector<std::string>;
  EXPECT_EQ(checks(metrics_of({{"effective_orifice_area", 2.0}, {"max_orifice_area", 1.9}})),
            names{"eoa_above_goa"});
  EXPECT_EQ(checks(metrics_of({{"effective_orifice_area", 1.9}, {"max_orifice_area", 2.0}})), names{});
  const double tolerance = hd::periodic_pressure_tolerance;
  EXPECT_EQ(checks(metrics_of(
                {{"windkessel_pressure_start", 70.0}, {"windkessel_pressure_end", 70.0 - 1.01 * tolerance}})),
            names{"not_periodic"});
  EXPECT_EQ(checks(metrics_of(
                {{"windkessel_pressure_start", 70.0}, {"windkessel_pressure_end", 70.0 + 0.99 * tolerance}})),
            names{});
  EXPECT_EQ(checks(metrics_of({})), names{}); // nothing to check without the figures
}

TEST(Report, TheReportOpensWithTheHeadlineThenThePlotsThenTheMetricsInGroups)
{
  const auto run = scratch("headline");
  write_cycles(run, 1, 300.0, 1.0, 3.0); // EOA about 3 cm^2 through a 1 cm^2 orifice; P_Wk drifts 3 mmHg
  std::ofstream(run / "extra_metrics.json") << R"({"fit_error": {"value": 1.25, "unit": "kPa"}})";
  hd::ReportOptions options;
  options.python = IBVALVE_PYTHON;
  const hd::ReportFiles files = hd::write_report(run, options);
  const hd::Json doc = hd::Json::parse(ibvalve::io::read_text_file(files.json));
  std::vector<std::string> flagged;
  for (const hd::Json& c : doc.at("checks")) flagged.push_back(c.at("check").get<std::string>());
  EXPECT_EQ(flagged, (std::vector<std::string>{"eoa_above_goa", "not_periodic"}));
  EXPECT_EQ(doc.at("metrics").at("fit_error").at("group"), "leaflet mechanics");
  EXPECT_EQ(doc.at("metrics").at("opening_duration").at("group"), "valve motion");
  EXPECT_EQ(doc.at("metrics").at("effective_orifice_area").at("group"), "flow and pressure");
  const std::string html = ibvalve::io::read_text_file(files.html);
  const auto headline = html.find("<table id=\"headline\">"), plots = html.find("<h2>Plots</h2>"),
             groups = html.find("<h3>flow and pressure</h3>"), motion = html.find("<h3>valve motion</h3>"),
             mechanics = html.find("<h3>leaflet mechanics</h3>");
  ASSERT_NE(headline, std::string::npos);
  EXPECT_LT(html.find("data-check=\"eoa_above_goa\""), headline);
  EXPECT_LT(headline, plots);
  EXPECT_LT(plots, groups);
  EXPECT_LT(groups, motion);
  EXPECT_LT(motion, mechanics);
  EXPECT_LT(mechanics, html.find("data-key=\"fit_error\""));
  EXPECT_NE(html.find("<tr data-headline=\"effective_orifice_area\">"), std::string::npos);
  EXPECT_NE(html.find("J Am Soc Echocardiogr 30:372-392"), std::string::npos);
  const std::string md = ibvalve::io::read_text_file(files.markdown);
  EXPECT_LT(md.find("## At a glance"), md.find("## Plots"));
  EXPECT_LT(md.find("> **Implausible:** EOA"), md.find("| figure |"));
  EXPECT_LT(md.find("## Plots"), md.find("### flow and pressure"));
  EXPECT_NE(md.find("| &lt; 20 (at most mild stenosis) | Baumgartner et al. 2017 |"), std::string::npos);
  // A metric without an uncertainty shows none: no empty "(u from )" and no "±".
  EXPECT_EQ(md.find("(u from"), std::string::npos);
  EXPECT_EQ(html.find("(u from"), std::string::npos);
  EXPECT_EQ(md.find("±"), std::string::npos);
  fs::remove_all(run);
  // A valve whose EOA is below its orifice, in a periodic cycle: nothing flagged.
  const auto fine = scratch("headline_fine");
  write_cycles(fine, 1, 300.0, 5.0, 0.0);
  options.plots = false;
  const hd::Json fine_doc =
      hd::Json::parse(ibvalve::io::read_text_file(hd::write_report(fine, options).json));
  EXPECT_TRUE(fine_doc.at("checks").empty()) << fine_doc.at("checks");
  EXPECT_EQ(ibvalve::io::read_text_file(fine / "report" / "report.html").find("Implausible"),
            std::string::npos);
  fs::remove_all(fine);
}

TEST(Report, EachCycleHasItsOwnReportCountedFromOneAndTheLastHoldsTheCycleToCycleTable)
{
  const auto run = scratch("cycles");
  write_cycles(run, 3, 300.0, 5.0, -0.5);
  hd::ReportOptions options;
  options.plots = false;
  const hd::ReportFiles files = hd::write_report(run, options);
  EXPECT_EQ(files.reported_cycle, 3);
  EXPECT_EQ(files.cycles, 3);
  ASSERT_EQ(files.cycle_pages.size(), 3u);
  std::vector<double> volumes;
  for (int c = 1; c <= 3; ++c) {
    const fs::path folder = run / "report" / ("cycle_" + std::to_string(c));
    EXPECT_EQ(files.cycle_pages[c - 1], folder / "report.html");
    const hd::Json doc = hd::Json::parse(ibvalve::io::read_text_file(folder / "metrics.json"));
    EXPECT_EQ(doc.at("cycle").at("number"), c);
    EXPECT_EQ(doc.at("cycle").at("of"), 3);
    EXPECT_NEAR(doc.at("phases").at("cycle_start").get<double>(), 0.8 * (c - 1), 1e-12);
    volumes.push_back(doc.at("metrics").at("forward_volume").at("value").get<double>());
    const std::string title =
        "<title>ibvalve report: ibvalve_test_report_cycles, cycle " + std::to_string(c) + " of 3</title>";
    EXPECT_NE(ibvalve::io::read_text_file(folder / "report.html").find(title), std::string::npos) << c;
    EXPECT_EQ(doc.at("cycles").size(), static_cast<std::size_t>(c)); // cycles 1 to this one
  }
  EXPECT_NEAR(volumes[1] / volumes[0], 1.1, 1e-9); // the lobes of 1, 1.1 and 1.2 x the amplitude
  // report/ is the reported (last) cycle's, and its table holds every cycle's V_F, TPG and P_Wk.
  const hd::Json doc = hd::Json::parse(ibvalve::io::read_text_file(files.json));
  EXPECT_EQ(files.json, run / "report" / "metrics.json");
  EXPECT_EQ(doc.at("cycle").at("number"), 3);
  const hd::Json& table = doc.at("cycles");
  ASSERT_EQ(table.size(), 3u);
  for (int c = 1; c <= 3; ++c) {
    EXPECT_EQ(table[c - 1].at("cycle"), c);
    EXPECT_EQ(table[c - 1].at("forward_volume").get<double>(), volumes[c - 1]);
    EXPECT_NEAR(table[c - 1].at("windkessel_pressure_end").get<double>() -
                    table[c - 1].at("windkessel_pressure_start").get<double>(),
                -0.5, 1e-9);
  }
  const std::string periodicity = doc.at("periodicity").get<std::string>();
  EXPECT_NE(periodicity.find("Cycle 3 against cycle 2: V_F by +9.1 %"), std::string::npos) << periodicity;
  EXPECT_NE(periodicity.find("-0.5 mmHg over the cycle: periodic"), std::string::npos) << periodicity;
  const std::string md = ibvalve::io::read_text_file(files.markdown);
  EXPECT_NE(md.find("# ibvalve report: ibvalve_test_report_cycles, cycle 3 of 3"), std::string::npos);
  EXPECT_NE(md.find("| [3](cycle_3/report.html) (this report) |"), std::string::npos);
  EXPECT_NE(ibvalve::io::read_text_file(run / "report" / "cycle_3" / "report.md")
                .find("| [1](../cycle_1/report.html) |"),
            std::string::npos);
  // Another cycle reported, into another folder.
  options.settings.cycle = 2;
  options.output = run / "elsewhere";
  const hd::ReportFiles second = hd::write_report(run, options);
  EXPECT_EQ(second.html, run / "elsewhere" / "report.html");
  EXPECT_EQ(hd::Json::parse(ibvalve::io::read_text_file(second.json)).at("cycle").at("number"), 2);
  fs::remove_all(run);
}

TEST(Report, EveryCyclesPageHasItsPlotsOrWithCyclePlotsOffOnlyTheReportedCyclesPage)
{
  const auto run = scratch("cycle_plots");
  write_cycles(run, 3, 300.0, 5.0, 0.0);
  hd::ReportOptions options; // plots on: one Python draws the three cycles' pages
  const hd::ReportFiles files = hd::write_report(run, options);
  const std::vector<std::string> images{"flow.png", "pressures.png", "pressure_difference.png",
                                        "orifice_area.png"};
  for (int c = 1; c <= 3; ++c)
    for (const std::string& image : images)
      EXPECT_TRUE(fs::exists(run / "report" / ("cycle_" + std::to_string(c)) / image)) << c << " " << image;
  // Each page draws its own cycle: the flow plots of cycles 1 and 2 (lobes of 1 and 1.1 x) differ.
  EXPECT_NE(ibvalve::io::read_text_file(run / "report" / "cycle_1" / "flow.png"),
            ibvalve::io::read_text_file(run / "report" / "cycle_2" / "flow.png"));
  EXPECT_EQ(files.plots.size(), images.size());
  EXPECT_EQ(ibvalve::io::read_text_file(run / "report" / "flow.png"),
            ibvalve::io::read_text_file(run / "report" / "cycle_3" / "flow.png"));

  options.cycle_plots = false; // again: the earlier cycles' images are removed, not left stale
  const hd::ReportFiles reported_only = hd::write_report(run, options);
  for (int c = 1; c <= 2; ++c) {
    const fs::path page = run / "report" / ("cycle_" + std::to_string(c));
    for (const std::string& image : images) EXPECT_FALSE(fs::exists(page / image)) << c << " " << image;
    EXPECT_EQ(ibvalve::io::read_text_file(page / "report.html").find(".png"), std::string::npos) << c;
  }
  for (const std::string& image : images) {
    EXPECT_TRUE(fs::exists(run / "report" / "cycle_3" / image)) << image;
    EXPECT_TRUE(fs::exists(run / "report" / image)) << image;
  }
  EXPECT_EQ(reported_only.plots.size(), images.size());
  fs::remove_all(run);
}

TEST(Report, ARunsEndOfCycleWritesThatCyclesFolderAndTheReportedOnesOnlyWhenItIsThatCycle)
{
  const auto run = scratch("cycle_end");
  write_cycles(run, 1, 300.0, 5.0, 0.0); // the run's first cycle of two has ended
  hd::ReportOptions options;
  options.plots = false;
  options.cycle_folders = hd::CycleFolders::last;
  options.run_cycles = 2;
  options.settings.cycle = 2; // report.cycle = 2: report/ waits for the second cycle
  hd::ReportFiles files = hd::write_report(run, options);
  EXPECT_EQ(files.html, run / "report" / "cycle_1" / "report.html");
  EXPECT_FALSE(fs::exists(run / "report" / "report.html"));
  options.settings.cycle = -1; // the last whole cycle: this one
  files = hd::write_report(run, options);
  EXPECT_EQ(files.cycle_pages, std::vector<fs::path>{run / "report" / "cycle_1" / "report.html"});
  EXPECT_EQ(files.html, run / "report" / "report.html");
  EXPECT_NE(ibvalve::io::read_text_file(files.html).find("cycle 1 of 2</title>"), std::string::npos);
  write_cycles(run, 2, 300.0, 5.0, 0.0); // and the second
  options.settings.cycle = 1;            // report.cycle = 1: report/ keeps the first's
  fs::remove_all(run / "report");
  files = hd::write_report(run, options);
  EXPECT_EQ(files.cycle_pages, std::vector<fs::path>{run / "report" / "cycle_2" / "report.html"});
  EXPECT_EQ(files.html, run / "report" / "cycle_2" / "report.html");
  EXPECT_FALSE(fs::exists(run / "report" / "report.html"));
  EXPECT_FALSE(fs::exists(run / "report" / "cycle_1"));
  fs::remove_all(run);
}

TEST(Report, AFitErrorAgainstSyntheticSamplesSaysSoOnTheReport)
{
  const auto run = scratch("synthetic");
  write_cycles(run, 1, 300.0, 5.0, 0.0);
  std::ofstream(run / "extra_metrics.json")
      << R"({"fit_error": {"value": 0.9, "unit": "kPa", "synthetic_data": true,
              "note": "3 of 3 sample(s) synthetic, drawn from the W1 curves"}})";
  hd::ReportOptions options;
  options.plots = false;
  const hd::ReportFiles files = hd::write_report(run, options);
  const hd::Json fit = hd::Json::parse(ibvalve::io::read_text_file(files.json)).at("metrics").at("fit_error");
  EXPECT_EQ(fit.at("synthetic_data"), true);
  EXPECT_NE(
      ibvalve::io::read_text_file(files.html).find("3 of 3 sample(s) synthetic, drawn from the W1 curves"),
      std::string::npos);
  EXPECT_NE(ibvalve::io::read_text_file(files.markdown).find("3 of 3 sample(s) synthetic"),
            std::string::npos);
  fs::remove_all(run);
}

namespace {

hd::CaseResult case_of(const std::string& name, double vf, double rf, std::optional<double> fit,
                       bool synthetic = false)
{
  hd::CaseResult c;
  c.name = name;
  auto entry = [](std::optional<double> v) {
    return hd::Json{{"value", v ? hd::Json(*v) : hd::Json()}, {"unit", ""}, {"symbol", ""}};
  };
  c.metrics =
      hd::Json{{"forward_volume", entry(vf)}, {"regurgitant_fraction", entry(rf)}, {"fit_error", entry(fit)}};
  if (synthetic) {
    c.metrics["fit_error"]["synthetic_data"] = true;
    c.metrics["fit_error"]["note"] = "3 of 3 sample(s) synthetic, drawn from a law's own curves";
  }
  return c;
}

} // namespace

TEST(Compare, TheRankingIsShownAndWrittenBestFirst)
{
  // Ranks: a 2, b 1, c 3 (the scores of ScalesEachCriterionBestToOneWorstToZeroAndLeavesOutMissingOnes).
  std::vector<hd::CaseResult> cases{case_of("a", 60, 10, 1.0), case_of("b", 80, 5, std::nullopt),
                                    case_of("c", 70, 20, 2.0)};
  const hd::Ranking r = hd::rank_cases(cases);
  EXPECT_EQ(r.by_rank, (std::vector<std::size_t>{1, 0, 2}));
  EXPECT_EQ(r.rows[0].name, "a"); // rows stay in the cases' order
  const auto out = scratch("compare_order");
  hd::ComparisonOptions pages_only;
  pages_only.plots = false;
  const auto files = hd::write_comparison(cases, out, pages_only);
  const std::string md = ibvalve::io::read_text_file(files.markdown);
  const auto ranking = md.find("## Ranking");
  EXPECT_LT(md.find("\n| b |", ranking), md.find("\n| a |", ranking));
  EXPECT_LT(md.find("\n| a |", ranking), md.find("\n| c |", ranking));
  const std::string csv = ibvalve::io::read_text_file(files.ranking_csv);
  EXPECT_LT(csv.find("\nb,"), csv.find("\na,"));
  EXPECT_LT(csv.find("\na,"), csv.find("\nc,"));
  const std::string html = ibvalve::io::read_text_file(files.html);
  const auto table = html.find("<table id=\"ranking\">");
  EXPECT_LT(html.find("<tr><td>b</td>", table), html.find("<tr><td>a</td>", table));
  EXPECT_LT(html.find("<tr><td>a</td>", table), html.find("<tr><td>c</td>", table));
  fs::remove_all(out);
}

TEST(Compare, TheComparisonShowsTheInputsThatDifferBetweenTheCases)
{
  std::vector<hd::CaseResult> cases{case_of("a", 60, 10, 1.0), case_of("b", 80, 5, 2.0)};
  cases[0].inputs = {{"name", "\"a\""},
                     {"time.step", "0.0001 s"},
                     {"structure.material.preset", "\"zhu2021-W1\""},
                     {"output.every", "10"}};
  cases[1].inputs = {{"name", "\"b\""},
                     {"time.step", "0.0001 s"},
                     {"structure.material.preset", "\"zhu2021-W2\""},
                     {"output.every", "5"},
                     {"fibers.rule", "\"FD2\""}};
  using Rows = std::vector<std::pair<std::string, std::vector<std::string>>>;
  EXPECT_EQ(hd::differing_inputs(cases),
            (Rows{{"structure.material.preset", {"\"zhu2021-W1\"", "\"zhu2021-W2\""}},
                  {"fibers.rule", {"(unset)", "\"FD2\""}}}));
  const auto out = scratch("compare_inputs");
  hd::ComparisonOptions pages_only;
  pages_only.plots = false;
  const auto files = hd::write_comparison(cases, out, pages_only);
  const std::string md = ibvalve::io::read_text_file(files.markdown);
  EXPECT_LT(md.find("## What differs between the cases"), md.find("## Metrics per case"));
  EXPECT_NE(md.find("| `structure.material.preset` | &quot;zhu2021-W1&quot; | &quot;zhu2021-W2&quot; |"),
            std::string::npos)
      << md;
  EXPECT_NE(ibvalve::io::read_text_file(files.html).find("<tr data-input=\"fibers.rule\">"),
            std::string::npos);
  // A run folder's inputs come from its config.toml.
  const auto run = scratch("compare_inputs_run");
  write_cycles(run, 1, 300.0, 5.0, 0.0);
  std::ofstream(run / "config.toml") << "name = \"r\"\n[time]\nstep = 0.0001\n";
  const hd::CaseResult loaded = hd::load_case(run);
  EXPECT_EQ(loaded.inputs,
            (std::vector<std::pair<std::string, std::string>>{{"name", "'r'"}, {"time.step", "0.0001"}}));
  fs::remove_all(run);
  fs::remove_all(out);
}

TEST(Compare, ACriterionMeasuredAgainstSyntheticDataSaysSoAndCanBeLeftOut)
{
  std::vector<hd::CaseResult> cases{case_of("a", 60, 10, 1.0, true), case_of("b", 80, 5, 2.0, true)};
  const std::size_t fit = criterion_index("fit_error");
  hd::Ranking ranked = hd::rank_cases(cases);
  EXPECT_TRUE(ranked.used[fit]);
  std::vector<std::string> notes = hd::criterion_notes(cases, ranked);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_EQ(
      notes[0].rfind("fit error: measured against synthetic data for a, b (3 of 3 sample(s) synthetic", 0),
      0u)
      << notes[0];
  EXPECT_NE(notes[0].find("--leave-out fit_error"), std::string::npos) << notes[0];
  const auto out = scratch("compare_synthetic");
  hd::ComparisonOptions options;
  options.plots = false;
  std::string md = ibvalve::io::read_text_file(hd::write_comparison(cases, out, options).markdown);
  EXPECT_NE(md.find("> **Note:** fit error: measured against synthetic data"), std::string::npos) << md;
  EXPECT_NE(md.find("(synthetic data: see the note under the ranking)"), std::string::npos) << md;
  // Left out on request: the ranking goes without it, and the note says so.
  const std::vector<std::string> leave_out{"fit_error"};
  const hd::Ranking without = hd::rank_cases(cases, leave_out);
  EXPECT_FALSE(without.used[fit]);
  EXPECT_EQ(without.left_out.front(),
            "fit_error (left out on request)"); // then the criteria these cases lack
  EXPECT_FALSE(without.rows[0].scores[fit].has_value());
  EXPECT_NE(hd::criterion_notes(cases, without)[0].find("it is left out of this ranking"), std::string::npos);
  options.leave_out = leave_out;
  md = ibvalve::io::read_text_file(hd::write_comparison(cases, out, options).markdown);
  EXPECT_NE(
      md.find(
          "2 of 12 criteria ranked; left out: fit_error (left out on request); max_orifice_area (missing"),
      std::string::npos);
  EXPECT_FALSE(hd::check_criteria(std::vector<std::string>{"fit_eror"}).empty());
  options.leave_out = {"fit_eror"};
  EXPECT_THROW(hd::write_comparison(cases, out, options), ibvalve::InputError);
  fs::remove_all(out);
}
