#pragma once
// diagnostics.csv of a grid model's run folder (docs/runs.md, "Progress and diagnostics"): one row a
// step with its wall time, the solvers' iterations and residuals, max |u| and the CFL number, and the
// same figures on the progress line. Kept out of timeseries.csv on purpose: wall times and iteration
// counts differ between runs, rank counts and restarts, and timeseries.csv is compared byte for byte.
#include <filesystem>
#include <string>
#include <vector>

#include <mpi.h>

#include "base/logger.hpp"
#include "io/files.hpp"

#include "fluid/flow_solver.hpp"

namespace ibvalve::app {

/// One figure of a step: its column in diagnostics.csv and, when `label` is not empty, its place on
/// the progress line ("fluid it 7").
using StepFigure = fluid::SolverFigure;

/// A step's figures: the solvers' (`solver`), then max |u| (cm/s) and the CFL number max|u| dt / h.
struct StepFigures {
  std::vector<StepFigure> solver;
  double max_velocity = 0.0;
  double cfl = 0.0;
};

/// "fluid it 7, max|u| 21.2 cm/s, CFL 0.0034": the figures as the progress line shows them.
std::string progress_details(const StepFigures& figures);

/// The last step of a fluid: its solves' figures (FlowSolver::last_solves), its largest speed and the
/// CFL number max|u| dt / h with its smallest spacing (on nested levels an upper bound). Collective.
StepFigures fluid_step_figures(const fluid::FlowSolver& fluid, double dt);

/// "fluid per step: convection 0.002 s, viscous 0.01 s, pressure 0.02 s, 4.3 solver iterations": the
/// averages of FlowSolver::statistics over the steps so far, for a run's summary.
std::string fluid_summary(const fluid::FlowSolver& fluid);

class StepDiagnostics {
 public:
  /// Rank 0 of `comm` opens RUN_DIR/diagnostics.csv with the columns step, t, wall_step, the solver
  /// columns of `layout`, max_velocity and cfl; on restart it first cuts the file back to the steps
  /// up to the checkpoint's `first_step` (rows are steps 1, 2, ...) and appends. A failure reaches
  /// every rank. Collective.
  StepDiagnostics(MPI_Comm comm, const std::filesystem::path& directory, const StepFigures& layout,
                  bool restart, long first_step);

  /// Rank 0 writes step `step`'s row: its wall time (since the previous row, or since construction:
  /// the step and the run's outputs around it) and `figures`, which must have the layout's columns.
  /// Returns the progress line's details of the step.
  std::string write(long step, double t, const StepFigures& figures);

 private:
  io::CsvWriter csv_;
  bool root_ = false;
  double last_wall_ = 0.0;
};

} // namespace ibvalve::app
