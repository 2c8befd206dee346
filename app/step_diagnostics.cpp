#include "app/step_diagnostics.hpp"

#include <algorithm>
#include <sstream>

#include "io/checkpoint.hpp"
#include "io/collective.hpp"

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

StepFigures fluid_step_figures(const fluid::FlowSolver& fluid, double dt)
{
  const double umax = fluid.max_velocity();
  return {fluid.last_solves(), umax, umax * dt / fluid.finest_spacing()};
}

std::string fluid_summary(const fluid::FlowSolver& fluid)
{
  const fluid::StepStatistics& s = fluid.statistics();
  const double n = static_cast<double>(std::max<PetscInt>(s.steps, 1));
  std::ostringstream line;
  line.precision(3);
  line << "fluid per step: convection " << s.convection / n << " s, viscous " << s.viscous / n
       << " s, pressure " << s.pressure / n << " s, " << static_cast<double>(s.solver_iterations) / n
       << " solver iterations";
  return line.str();
}

StepDiagnostics::StepDiagnostics(MPI_Comm comm, const std::filesystem::path& directory,
                                 const StepFigures& layout, bool restart, long first_step)
{
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  root_ = rank == 0;
  // The units line as in timeseries.csv (docs/runs.md); the CFL number is a pure number.
  std::vector<std::string> columns{"step", "t", "wall_step"}, units{"1", "s", "s"};
  for (const StepFigure& f : layout.solver) {
    columns.push_back(f.column);
    units.push_back(f.unit);
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
        base::Logger::global().warn(std::string(e.what()) + "; diagnostics.csv starts anew");
        append = false;
      }
    }
    csv_ = io::CsvWriter(path, columns, append, units);
  });
  last_wall_ = base::Logger::global().wall_seconds();
}

std::string StepDiagnostics::write(long step, double t, const StepFigures& figures)
{
  const double wall = base::Logger::global().wall_seconds();
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
