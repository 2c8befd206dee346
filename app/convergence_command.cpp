// `ibvalve convergence RUN_DIR... [-o DIR]`: the grid convergence of every metric of runs of one case on
// different grids (hemodynamics/convergence_study.hpp): convergence.md, convergence.csv, convergence.json.
#include <filesystem>
#include <memory>
#include <vector>

#include <fmt/format.h>
#include <petscsys.h>

#include "app/commands.hpp"
#include "base/logger.hpp"
#include "hemodynamics/convergence_study.hpp"
#include "hemodynamics/report.hpp"
#include "io/collective.hpp"

namespace ibvalve::app {

namespace {

struct ConvergenceOptions {
  std::vector<std::filesystem::path> runs;
  std::filesystem::path output = "convergence";
};

int study_convergence(const ConvergenceOptions& options)
{
  io::on_root(PETSC_COMM_WORLD, [&] {
    const hemodynamics::ConvergenceStudy study = hemodynamics::study_grid_convergence(options.runs);
    const auto files = hemodynamics::write_grid_convergence(study, options.output);
    auto& log = base::Logger::global();
    for (const auto& r : study.runs)
      log.info(fmt::format("grid {}: h = {} cm", r.run.name, hemodynamics::format_value(r.spacing)));
    for (const auto& m : study.metrics) {
      const auto& g = m.result;
      log.info(fmt::format("{}: {}, GCI {} {}{}", m.key, hemodynamics::to_string(g.kind),
                           hemodynamics::format_value(g.uncertainty), m.unit,
                           g.p ? ", p = " + hemodynamics::format_value(*g.p) : std::string()));
    }
    for (const auto& left : study.left_out) log.info("left out: " + left);
    log.info("convergence: " + files.markdown.string() + ", " + files.csv.string() + ", " +
             files.json.string());
  });
  return 0;
}

} // namespace

void add_convergence_command(CLI::App& app, CommandAction& action)
{
  auto options = std::make_shared<ConvergenceOptions>();
  CLI::App* sub = app.add_subcommand(
      "convergence", "Grid convergence of every metric of runs on different grids (Celik et al. 2008 GCI)");
  sub->add_option("runs", options->runs, "run folders of one case on different grids, in any order")
      ->required();
  sub->add_option("-o,--output", options->output, "folder for convergence.{md,csv,json}")
      ->check(non_empty_path);
  sub->callback([options, &action] {
    action = [options](const PetscArguments&) { return study_convergence(*options); };
  });
}

} // namespace ibvalve::app
