// ibvalve: the command line. Parses the subcommand with CLI11, starts MPI and PETSc, runs it, and maps
// failures to exit codes: 2 for bad input (one line naming file, line and key), 3 for a run that
// went wrong (its output so far is kept).
#include <cstring>
#include <fmt/format.h>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <petscsys.h>

#include "app/commands.hpp"
#include "base/build_info.hpp"
#include "base/errors.hpp"
#include "base/logger.hpp"

namespace {

int rank_of_world()
{
  int initialized = 0, rank = 0;
  MPI_Initialized(&initialized);
  if (initialized) MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

} // namespace

int main(int argc, char** argv)
{
  using namespace ibvalve;

  // Everything after "--" is for PETSc.
  std::vector<char*> ours(argv, argv + argc);
  app::PetscArguments petsc_arguments;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--") == 0) {
      ours.assign(argv, argv + i);
      petsc_arguments.options.assign(argv + i + 1, argv + argc);
      break;
    }
  }
  std::vector<char*> petsc_argv{argv[0]};
  for (auto& option : petsc_arguments.options) petsc_argv.push_back(option.data());
  int petsc_argc = static_cast<int>(petsc_argv.size());
  char** petsc_argv_ptr = petsc_argv.data();
  if (PetscInitialize(&petsc_argc, &petsc_argv_ptr, nullptr, nullptr) != 0) return 1;
  base::Logger::global().set_communicator(PETSC_COMM_WORLD);

  CLI::App cli{"ibvalve: immersed-boundary / finite-element heart-valve simulator.\n"
               "Case-file keys: ibvalve keys [MODEL] (--format toml for a case skeleton).\n" +
                   app::petsc_options_help(),
               "ibvalve"};
  cli.set_version_flag("--version",
                       fmt::format("ibvalve {} (PETSc {}.{}.{})", base::version(), PETSC_VERSION_MAJOR,
                                   PETSC_VERSION_MINOR, PETSC_VERSION_SUBMINOR));
  cli.require_subcommand(1);
  app::CommandAction action;
  app::add_run_command(cli, action);
  app::add_check_command(cli, action);
  app::add_keys_command(cli, action);
  // A build of a subset of the folders (IBVALVE_FOLDERS) has the subcommands whose folders it has.
#if IBVALVE_HAVE_MATERIALS
  app::add_fit_command(cli, action);
#endif
#if IBVALVE_HAVE_FE
  app::add_mesh_command(cli, action);
#endif
#if IBVALVE_HAVE_FIBERS
  app::add_fibers_command(cli, action);
#endif
#if IBVALVE_HAVE_HEMODYNAMICS
  app::add_report_command(cli, action);
  app::add_compare_command(cli, action);
  app::add_convergence_command(cli, action);
  app::add_study_command(cli, action);
#endif

  int code = 0;
  try {
    cli.parse(static_cast<int>(ours.size()), ours.data());
  } catch (const CLI::ParseError& error) {
    // Help and version are "errors" with exit code 0 in CLI11; a real usage error is bad input.
    if (error.get_exit_code() == 0) {
      if (rank_of_world() == 0) cli.exit(error);
    } else {
      base::Logger::global().error("command line: " + std::string(error.what()) + " (see ibvalve --help)");
      code = exit_code_input_error;
    }
    PetscFinalize();
    return code;
  }

  try {
    code = action(petsc_arguments);
  } catch (const InputError& error) {
    base::Logger::global().error(error.what());
    code = exit_code_input_error;
  } catch (const RunError& error) {
    base::Logger::global().error(error.what());
    base::Logger::global().error("the run stopped; all output so far is kept");
    code = exit_code_run_error;
  } catch (const std::exception& error) {
    base::Logger::global().error(std::string("internal error: ") + error.what());
    code = 1;
  }
  base::Logger::global().close_file();
  PetscFinalize();
  return code;
}
