// `ibvalve report RUN_DIR`: metrics.json, report.md and report.html (with matplotlib plots) for a run
// folder's timeseries.csv: the reported cycle's in RUN_DIR/report (or -o DIR), each cycle's in its
// cycle_N/ there. Metric settings (and the templates folder) come from the run's config.toml
// ([report] table) unless given on the command line. `ibvalve report --write-templates DIR` copies the
// built-in templates (the report's and the comparison's) out for restyling.
#include <filesystem>
#include <fmt/format.h>
#include <memory>
#include <optional>

#include <mpi.h>
#include <petscsys.h>

#include "app/commands.hpp"
#include "base/errors.hpp"
#include "base/logger.hpp"
#include "hemodynamics/report.hpp"
#include "io/collective.hpp"

namespace ibvalve::app {

namespace {

struct ReportCommandOptions {
  std::filesystem::path run_directory;
  std::string python = hemodynamics::default_python();
  bool no_plots = false;
  std::optional<double> period;
  std::optional<int> cycle;
  std::optional<std::string> closure_rule;
  std::optional<std::filesystem::path> templates;
  std::optional<std::filesystem::path> write_templates;
  std::filesystem::path output; // empty = RUN_DIR/report
};

int report(const ReportCommandOptions& options)
{
  io::on_root(PETSC_COMM_WORLD, [&] {
    if (options.write_templates) {
      for (const auto& file : hemodynamics::write_builtin_templates(*options.write_templates))
        base::Logger::global().info("template: " + file.string());
      return;
    }
    hemodynamics::ReportOptions report_options;
    // The run's own settings (its config.toml's [report] table: the period of its cycle, the density)
    // unless given here; a given period is checked against the run's cycle.
    const hemodynamics::RecordedReport recorded = hemodynamics::recorded_report(options.run_directory);
    report_options.settings = recorded.report.metrics;
    report_options.run_period = recorded.period;
    if (options.period) report_options.settings.period = *options.period;
    report_options.period_given = options.period.has_value();
    if (options.cycle == 0)
      throw InputError("--cycle 0: cycles count from 1 (1 = the first, -1 = the last whole cycle)");
    if (options.cycle) report_options.settings.cycle = *options.cycle;
    if (options.closure_rule)
      report_options.settings.closure_rule = hemodynamics::closure_rule_from_name(*options.closure_rule);
    report_options.python = options.python;
    report_options.plots = !options.no_plots;
    report_options.cycle_plots = recorded.report.cycle_plots;
    report_options.templates = options.templates ? *options.templates : recorded.report.templates;
    report_options.output = options.output;
    const auto files = hemodynamics::write_report(options.run_directory, report_options);
    auto& log = base::Logger::global();
    for (std::size_t c = 0; c < files.cycle_pages.size(); ++c)
      log.info(fmt::format("cycle {} of {} report: {}", c + 1, files.cycles, files.cycle_pages[c].string()));
    log.info(fmt::format("metrics of the reported cycle ({} of {}): {}", files.reported_cycle, files.cycles,
                         files.json.string()));
    log.info(fmt::format("report:  {} (and report.md, {} plots)", files.html.string(), files.plots.size()));
  });
  return 0;
}

} // namespace

void add_report_command(CLI::App& app, CommandAction& action)
{
  auto options = std::make_shared<ReportCommandOptions>();
  CLI::App* sub = app.add_subcommand(
      "report",
      "Write RUN_DIR/report/: metrics.json, report.md, report.html and plots from RUN_DIR/timeseries.csv");
  CLI::Option* run = sub->add_option("run", options->run_directory, "the run folder");
  sub->add_option("--python", options->python,
                  "Python with matplotlib and numpy (default: the one CMake found)");
  sub->add_flag("--no-plots", options->no_plots, "skip the plots");
  sub->add_option("--period", options->period,
                  "cardiac cycle, s (default: report.period of the run, else 0.8; another than the "
                  "run's is warned about, one longer than the series or under 10 rows refused)")
      ->check(CLI::PositiveNumber);
  sub->add_option(
         "--cycle", options->cycle,
         "the reported cycle, counted from 1 (-1 = the last whole; default: report.cycle of the run)")
      ->check(CLI::Range(-1, 1000000));
  sub->add_option("-o,--output", options->output,
                  "folder of the report (default: RUN_DIR/report): the reported cycle's report there, every "
                  "cycle's in its cycle_N/")
      ->check(non_empty_path);
  sub->add_option("--closure-rule", options->closure_rule, "how the closure instant is found")
      ->check(CLI::IsMember({"auto", "flow", "area"}));
  sub->add_option("--templates", options->templates,
                  "folder of report.html.tpl and/or report.md.tpl to lay the report out with (default: "
                  "report.templates of the run, else the built-in ones)");
  sub->add_option("--write-templates", options->write_templates,
                  "write the built-in templates of the report and of `ibvalve compare` "
                  "(report.{html,md}.tpl, comparison.{html,md}.tpl) into this folder, to restyle them, "
                  "instead of a report")
      ->excludes(run);
  sub->callback([options, run, &action] {
    if (!options->write_templates && run->count() == 0) throw CLI::RequiredError("run");
    action = [options](const PetscArguments&) { return report(*options); };
  });
}

} // namespace ibvalve::app
