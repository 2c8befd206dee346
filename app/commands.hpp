#pragma once
// The `ibvalve` subcommands. Each adds itself to the CLI11 application and, once parsed, runs with
// MPI and PETSc initialised; its return value is the process exit code.
#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace ibvalve::app {

/// Options given after `--` on the command line, handed to PETSc unchanged.
struct PetscArguments {
  std::vector<std::string> options;
  /// Joined for PetscOptionsInsertString.
  std::string joined() const;
};

using CommandAction = std::function<int(const PetscArguments&)>;

/// Registers `ibvalve run CASE.toml`; sets `action` when the subcommand is chosen.
void add_run_command(CLI::App& app, CommandAction& action);
/// Registers `ibvalve fit --law W1 DATA.csv ...` (planar biaxial fitting, materials/fitting.hpp).
void add_fit_command(CLI::App& app, CommandAction& action);
/// Registers `ibvalve fibers MESH.msh --rule FD1|FD2 -o OUT` (fibers/rules.hpp).
void add_fibers_command(CLI::App& app, CommandAction& action);

} // namespace ibvalve::app
