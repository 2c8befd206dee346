#include "app/ibfe_run_loop.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>

#include <mpi.h>

#include "app/ibfe_fields.hpp"
#include "app/restart.hpp"
#include "app/stop_signal.hpp"
#include "io/collective.hpp"
#include "io/files.hpp"
#include "io/logger.hpp"

namespace ibvalve::app {

RunSummary run_ibfe_loop(const RunContext& context, ib::IbfeIntegrator& ibfe, const fe::Mesh& mesh,
                         const IbfeLoopSettings& settings, const IbfeFluidHooks& fluid)
{
  auto& log = io::Logger::global();
  const std::filesystem::path& directory = context.run_directory;
  create_fields_directory(context.comm, directory);
  io::XdmfTimeSeries series(context.comm, directory / "fields.xdmf");
  // A checkpoint holds the fluid's state and the structure's (docs/runs.md).
  const io::Checkpoints checkpoints(context.comm, directory, settings.checkpoints);
  const long steps = std::max(1L, std::lround(settings.end / settings.dt));
  long first_step = 0;
  std::int64_t rows = 0;
  if (context.restart) {
    const io::CheckpointHeader header =
        restart_from_latest(checkpoints, context, steps, [&](const io::Hdf5File& h5) {
          fluid.restore(h5);
          ibfe.restore(h5, "ibfe");
        });
    first_step = static_cast<long>(header.step);
    rows = header.timeseries_rows;
    series.resume(ibfe.time());
  }
  io::CsvWriter csv; // rank 0's; a failure to open it reaches every rank
  io::on_root(context.comm, [&] {
    csv = io::CsvWriter(
        directory / "timeseries.csv",
        {"t", "volume", "volume_change", "max_node_speed", "max_displacement", "kinetic_energy"},
        context.restart, {"s", "cm^3", "1", "cm/s", "cm", "erg"});
  });
  const double V0 = mesh.volume();
  auto record = [&](long step) {
    double speed = 0.0, displacement = 0.0;
    for (std::size_t n = 0; n < mesh.num_nodes(); ++n) {
      speed = std::max(speed, Eigen::Vector3d(ibfe.velocity().data() + 3 * n).norm());
      displacement = std::max(displacement, Eigen::Vector3d(ibfe.displacement().data() + 3 * n).norm());
    }
    const double volume = ibfe.volume(), energy = fluid.kinetic_energy();
    // Rank 0's row; a failure to write it (a full disk) reaches every rank.
    io::on_root(context.comm, [&] {
      csv.write_row({ibfe.time(), volume, volume / V0 - 1.0, speed, displacement, energy});
    });
    ++rows;
    if (step % settings.output_every == 0 || step == steps) fluid.write_fields(series, step);
  };
  auto save = [&](long step) {
    return checkpoints.write({step, ibfe.time(), rows}, [&](io::Hdf5File& h5) {
      fluid.save(h5);
      ibfe.save(h5, "ibfe");
    });
  };
  // The fluid's figures and the structure's projections (0 iterations for the default direct solves).
  auto figures = [&] {
    StepFigures f = fluid.step_figures(settings.dt);
    f.solver.push_back(
        {"structure_iterations", static_cast<double>(ibfe.last_projection_iterations()), "structure it"});
    return f;
  };
  StepDiagnostics diagnostics(context.comm, directory, figures(), context.restart, first_step);
  if (!context.restart) record(0);
  long last_step = static_cast<long>(last_step_of_invocation(context, first_step, steps));
  int stop_signal = 0;
  std::filesystem::path saved; // the checkpoint of the step just taken, if it wrote one
  log.begin_steps(first_step, last_step);
  for (long step = first_step + 1; step <= last_step; ++step) {
    ibfe.step(settings.dt);
    const StepFigures f = figures();
    record(step);
    log.progress({step, steps, ibfe.time(), static_cast<double>(steps) * settings.dt,
                  diagnostics.write(step, ibfe.time(), f)});
    saved.clear();
    if (checkpoints.due(step, steps)) saved = save(step);
    // SIGINT/SIGTERM (app/stop_signal.hpp): every rank stops after this step.
    if (step < steps && (stop_signal = agreed_stop_signal(context.comm)) != 0) {
      last_step = step;
      break;
    }
  }
  log.finish_progress();
  RunSummary summary;
  if (last_step < steps)
    add_stop(summary, last_step, steps, saved.empty() ? save(last_step) : saved, directory, stop_signal);
  for (std::string& line : ibfe_summary_lines(ibfe, V0, directory, series.steps(),
                                              fluid.solver_summary ? fluid.solver_summary() : std::string()))
    summary.lines.push_back(std::move(line));
  return summary;
}

} // namespace ibvalve::app
