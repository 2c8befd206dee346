#pragma once
// The `ibvalve` subcommands. Each adds itself to the CLI11 application and, once parsed, runs with
// MPI and PETSc initialised; its return value is the process exit code.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <mpi.h>

#include "app/model.hpp"
#include "hemodynamics/compare.hpp"

namespace ibvalve::app {

/// Options given after `--` on the command line, handed to PETSc unchanged.
struct PetscArguments {
  std::vector<std::string> options;
  /// Joined for PetscOptionsInsertString.
  std::string joined() const;
};

using CommandAction = std::function<int(const PetscArguments&)>;

/// For the -o and other path options: an empty path ("") is refused as a usage error (exit 2), not
/// taken as the option left out.
inline const CLI::Validator non_empty_path{
    [](std::string& value) { return value.empty() ? std::string("an empty path was given") : std::string(); },
    "PATH"};

/// The PETSc options prefixes of the solvers `ibvalve run` uses, with an example (for --help).
std::string petsc_options_help();

/// Registers `ibvalve run CASE.toml`; sets `action` when the subcommand is chosen.
void add_run_command(CLI::App& app, CommandAction& action);
/// What `ibvalve run` is told on its command line.
struct RunOptions {
  std::filesystem::path case_file;
  std::filesystem::path output;
  std::vector<std::string> overrides; // --set key=value
  std::filesystem::path restart;      // --restart RUN_DIR (then case_file stays empty)
  std::int64_t stop_after_steps = 0;  // --stop-after-steps N
  bool overwrite = false;
  bool verbose = false;
  bool quiet = false;
  bool strict = false; // --strict: a warning is an error (exit 2)
};
/// Validates and runs one case (what `ibvalve run` does; `ibvalve study` calls it once per case).
int run_case(RunOptions options, const PetscArguments& petsc);
/// A case read with its overrides and its model prepared: every check a run makes before it writes
/// anything (app/model.hpp).
struct PreparedCase {
  io::Config config;
  const Model* model = nullptr;
  std::unique_ptr<PreparedRun> run;
};
/// Reads `options.case_file` with `options.overrides`, sets the log level, prints the case's warnings,
/// takes the case's and the command line's PETSc options and prepares the model: InputError on bad
/// input, nothing written.
PreparedCase prepare_case(const RunOptions& options, const PetscArguments& petsc);
/// Registers `ibvalve check CASE [--set key=value ...]` (app/check_command.cpp).
void add_check_command(CLI::App& app, CommandAction& action);
/// Registers `ibvalve keys [MODEL] [--format markdown|toml]` (app/keys_command.cpp).
void add_keys_command(CLI::App& app, CommandAction& action);
/// Registers `ibvalve study STUDY.toml` (app/study_command.cpp).
void add_study_command(CLI::App& app, CommandAction& action);
/// Registers `ibvalve fit --law W1 DATA.csv ...` (planar biaxial fitting, materials/fitting.hpp).
void add_fit_command(CLI::App& app, CommandAction& action);
/// Registers `ibvalve mesh aortic-valve ... -o valve.msh` (fe/valve_mesh.hpp).
void add_mesh_command(CLI::App& app, CommandAction& action);
/// Registers `ibvalve fibers MESH.msh --rule FD1|FD2 -o OUT` (fibers/rules.hpp).
void add_fibers_command(CLI::App& app, CommandAction& action);

/// Registers `ibvalve report RUN_DIR` (hemodynamics/report.hpp).
void add_report_command(CLI::App& app, CommandAction& action);
/// Registers `ibvalve compare RUN_DIR...` (hemodynamics/compare.hpp).
void add_compare_command(CLI::App& app, CommandAction& action);
/// What `ibvalve compare RUNS... -o OUTPUT [--templates DIR] [--python P] [--no-plots]` does (also the
/// last step of `ibvalve study`, with the built-in templates and the build's Python).
int compare_runs(const std::vector<std::filesystem::path>& runs, const std::filesystem::path& output,
                 const hemodynamics::ComparisonOptions& options);
/// Registers `ibvalve convergence RUN_DIR... [-o DIR]` (hemodynamics/convergence_study.hpp).
void add_convergence_command(CLI::App& app, CommandAction& action);

} // namespace ibvalve::app
