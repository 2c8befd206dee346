#include "app/step_diagnostics.hpp"

#include <algorithm>
#include <sstream>

#include "fluid/navier_stokes.hpp"
#include "fluid/nested_navier_stokes.hpp"
#include "fluid/queries.hpp"
#include "io/checkpoint.hpp"
#include "io/collective.hpp"
#include "io/petsc_check.hpp"

namespace ibvalve::app {

std::string progress_details(const StepFigures& figures)
{
  std::ostringstream s;
  s.precision(3);
  for (const StepFigure& f : figures.solver)
    if (!f.label.empty()) s << f.label << " " << f.value << ", ";
  s << "max|u| " << figures.max_velocity << " cm/s, CFL " << figures.cfl;
  return s.str();
}

StepFigures fluid_step_figures(const fluid::NavierStokes& fluid, double dt)
{
  const fluid::SolveStatistics& solve = fluid.last_solve();
  const double h = std::min({fluid.grid().h(0), fluid.grid().h(1), fluid.grid().h(2)});
  const double umax = fluid::max_velocity_magnitude(fluid);
  return {{{"fluid_iterations", static_cast<double>(solve.iterations), "fluid it"},
           {"fluid_residual", solve.residual, ""}},
          umax,
          umax * dt / h};
}

StepFigures fluid_step_figures(const fluid::NestedNavierStokes& fluid, double dt)
{
  const fluid::NestedStepStatistics& stats = fluid.statistics();
  const fluid::GridHierarchy& levels = fluid.hierarchy();
  const int finest = levels.finest();
  const double h = std::min({levels.h(finest, 0), levels.h(finest, 1), levels.h(finest, 2)});
  PetscReal umax = 0.0;
  PETSC_CHECK(VecNorm(fluid.velocity(), NORM_INFINITY, &umax));
  return {{{"velocity_iterations", static_cast<double>(stats.velocity_iterations), "viscous it"},
           {"pressure_iterations", static_cast<double>(stats.pressure_iterations), "pressure it"}},
          static_cast<double>(umax),
          static_cast<double>(umax) * dt / h};
}

StepDiagnostics::StepDiagnostics(MPI_Comm comm, const std::filesystem::path& directory,
                                 const StepFigures& layout, bool restart, long first_step)
{
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  root_ = rank == 0;
  // The units line as in timeseries.csv (docs/runs.md); iteration counts, residuals and the CFL
  // number are pure numbers.
  std::vector<std::string> columns{"step", "t", "wall_step"}, units{"1", "s", "s"};
  for (const StepFigure& f : layout.solver) {
    columns.push_back(f.column);
    units.push_back("1");
  }
  columns.push_back("max_velocity");
  units.push_back("cm/s");
  columns.push_back("cfl");
  units.push_back("1");
  const std::filesystem::path path = directory / "diagnostics.csv";
  io::on_root(comm, [&] {
    // A folder from before diagnostics.csv existed starts a new one; otherwise the steps after the
    // checkpoint, which this run takes again, go.
    bool append = restart && std::filesystem::exists(path);
    if (append) {
      try {
        io::truncate_csv_rows(path, first_step);
      } catch (const std::exception& e) {
        // Diagnostics are no part of the state: a file that cannot be continued is started anew.
        io::Logger::global().warn(std::string(e.what()) + "; diagnostics.csv starts anew");
        append = false;
      }
    }
    csv_ = io::CsvWriter(path, columns, append, units);
  });
  last_wall_ = io::Logger::global().wall_seconds();
}

std::string StepDiagnostics::write(long step, double t, const StepFigures& figures)
{
  const double wall = io::Logger::global().wall_seconds();
  if (root_) {
    std::vector<double> row{static_cast<double>(step), t, wall - last_wall_};
    for (const StepFigure& f : figures.solver) row.push_back(f.value);
    row.push_back(figures.max_velocity);
    row.push_back(figures.cfl);
    csv_.write_row(row);
  }
  last_wall_ = wall;
  return progress_details(figures);
}

} // namespace ibvalve::app
