// `ibvalve compare RUN_DIR...`: the inputs that differ, every metric per case and the 12-criterion
// ranking in rank order, as Markdown, CSV and HTML (hemodynamics/compare.hpp).
#include <filesystem>
#include <memory>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <petscsys.h>

#include "app/commands.hpp"
#include "base/logger.hpp"
#include "hemodynamics/compare.hpp"
#include "hemodynamics/report.hpp"
#include "io/collective.hpp"

namespace ibvalve::app {

namespace {

struct CompareOptions {
  std::vector<std::filesystem::path> runs;
  std::filesystem::path output = "comparison";
  std::filesystem::path templates; // empty = the built-in templates
  std::string python = hemodynamics::default_python();
  bool no_plots = false;
  std::vector<std::string> leave_out;
};

} // namespace

int compare_runs(const std::vector<std::filesystem::path>& runs, const std::filesystem::path& output,
                 const hemodynamics::ComparisonOptions& options)
{
  io::on_root(PETSC_COMM_WORLD, [&] {
    std::vector<hemodynamics::CaseResult> cases;
    for (const auto& run : runs) cases.push_back(hemodynamics::load_case(run));
    hemodynamics::distinguish_case_names(cases);
    const auto files = hemodynamics::write_comparison(cases, output, options);
    const auto ranking = hemodynamics::rank_cases(cases, options.leave_out);
    auto& log = base::Logger::global();
    for (const std::size_t i : ranking.by_rank) {
      const auto& row = ranking.rows[i];
      log.info(
          fmt::format("rank {}: {} (total {})", row.rank, row.name, hemodynamics::format_value(row.total)));
    }
    for (const auto& left : ranking.left_out) log.info("left out of the ranking: " + left);
    for (const auto& note : hemodynamics::criterion_notes(cases, ranking)) log.warn(note);
    for (const auto& [key, values] : hemodynamics::differing_inputs(cases))
      log.info(fmt::format("differs: {}: {}", key, fmt::join(values, " | ")));
    log.info("comparison: " + files.html.string() + ", " + files.markdown.string() + ", " +
             files.metrics_csv.string() + ", " + files.ranking_csv.string() +
             fmt::format(" ({} plots)", files.plots.size()));
  });
  return 0;
}

void add_compare_command(CLI::App& app, CommandAction& action)
{
  auto options = std::make_shared<CompareOptions>();
  CLI::App* sub =
      app.add_subcommand("compare", "Compare run folders: metrics table and 12-criterion ranking");
  sub->add_option("runs", options->runs, "run folders")->required();
  sub->add_option("-o,--output", options->output, "folder for comparison.{md,html}, metrics.csv, ranking.csv")
      ->check(non_empty_path);
  sub->add_option("--templates", options->templates,
                  "folder of comparison.html.tpl and/or comparison.md.tpl to lay the pages out with "
                  "(`ibvalve report --write-templates DIR` writes the built-in ones)");
  sub->add_option("--python", options->python,
                  "the Python interpreter that draws the overlaid curves (needs matplotlib and numpy)");
  sub->add_flag("--no-plots", options->no_plots, "skip the overlaid curves");
  std::vector<std::string> criteria;
  for (const auto& criterion : hemodynamics::ranking_criteria()) criteria.push_back(criterion.key);
  sub->add_option(
         "--leave-out", options->leave_out,
         "a ranking criterion (its metric key, e.g. fit_error) left out of the ranking; repeat for more")
      ->check(CLI::IsMember(criteria));
  sub->callback([options, &action] {
    action = [options](const PetscArguments&) {
      return compare_runs(options->runs, options->output,
                          {options->templates, options->python, !options->no_plots, options->leave_out});
    };
  });
}

} // namespace ibvalve::app
