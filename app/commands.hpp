#pragma once
// The `ibvalve` subcommands. Each adds itself to the CLI11 application and, once parsed, runs with
// MPI and PETSc initialised; its return value is the process exit code.
#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <mpi.h>

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
/// Registers `ibvalve mesh aortic-valve ... -o valve.msh` (fe/valve_mesh.hpp).
void add_mesh_command(CLI::App& app, CommandAction& action);
/// Registers `ibvalve fibers MESH.msh --rule FD1|FD2 -o OUT` (fibers/rules.hpp).
void add_fibers_command(CLI::App& app, CommandAction& action);

/// Registers `ibvalve report RUN_DIR` (hemodynamics/report.hpp).
void add_report_command(CLI::App& app, CommandAction& action);
/// Registers `ibvalve compare RUN_DIR...` (hemodynamics/compare.hpp).
void add_compare_command(CLI::App& app, CommandAction& action);
/// Runs `work` on rank 0 of `comm` only and rethrows its InputError/RunError/other error on every rank.
void run_on_root_rank(MPI_Comm comm, const std::function<void()>& work);

} // namespace ibvalve::app
