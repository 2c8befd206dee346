// `ibvalve check CASE [--set key=value ...]`: every check `ibvalve run` makes before it writes anything
// (the case's keys, its files, the model's own checks: a valve's mesh and its groups, its fibers and
// materials), without running it or writing anything. Exit 0 with one line saying what the case is;
// bad input is exit 2 with its error line, as `ibvalve run` gives it.
#include <iostream>
#include <memory>
#include <string>

#include <fmt/format.h>
#include <mpi.h>

#include "app/commands.hpp"
#include "app/model.hpp"
#include "base/errors.hpp"
#include "io/collective.hpp"

namespace ibvalve::app {

namespace {

int check_case(const RunOptions& options, const PetscArguments& petsc)
{
  const PreparedCase prepared = prepare_case(options, petsc);
  std::string line = fmt::format("{}: a valid {} case", options.case_file.string(), prepared.model->name);
  if (const std::string summary = prepared.run->summary(); !summary.empty()) line += "; " + summary;
  if (!prepared.run->memory_line().empty()) line += "; " + prepared.run->memory_line();
  io::on_root(MPI_COMM_WORLD, [&] { std::cout << line << "\n" << std::flush; });
  return 0;
}

} // namespace

void add_check_command(CLI::App& app, CommandAction& action)
{
  auto options = std::make_shared<RunOptions>();
  CLI::App* sub = app.add_subcommand(
      "check", "Check a case file as `ibvalve run` would (keys, files, a valve's mesh, fibers and materials) "
               "without running it or writing anything: one line when it is valid, its error otherwise");
  sub->add_option("case", options->case_file, "the case file (TOML)")->required();
  sub->add_option("--set", options->overrides,
                  "override a key as `ibvalve run --set` does (a file relative to the working folder)");
  sub->add_flag("--strict", options->strict, "a warning is an error, as with `ibvalve run --strict`");
  sub->callback([options, &action] {
    action = [options](const PetscArguments& petsc) { return check_case(*options, petsc); };
  });
}

} // namespace ibvalve::app
