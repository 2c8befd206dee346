#include "app/time_loop.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <optional>
#include <string>

#include "app/launch_command.hpp"
#include "app/stop_signal.hpp"
#include "base/errors.hpp"
#include "base/logger.hpp"
#include "io/collective.hpp"
#include "io/files.hpp"

namespace ibvalve::app {

namespace {

/// On --restart: reads the checkpoint `ibvalve run` chose through `restore`, records the case
/// (context.accept_restart), cuts timeseries.csv back to the rows it had then and logs where the run
/// goes on from. InputError, before anything is written or cut, when there is no checkpoint or it is
/// already at or past the run's last step.
io::CheckpointHeader restart(const io::Checkpoints& checkpoints, const RunContext& context, MPI_Comm comm,
                             std::int64_t steps, const std::function<void(const io::Hdf5File&)>& restore)
{
  const std::filesystem::path& file = context.checkpoint;
  if (file.empty())
    throw InputError(context.run_directory.string() + ": no checkpoint to restart from (checkpoint.every)");
  const io::CheckpointHeader header = checkpoints.read(file, restore);
  if (header.step >= steps)
    throw InputError(fmt::format("{}: the checkpoint is at step {} but the run now ends at step {}: nothing "
                                 "to continue (lengthen the run with --set)",
                                 file.string(), header.step, steps));
  // Rank 0 alone writes config.toml and timeseries.csv; the others wait, so that nobody appends before
  // the cut, and learn of any failure there.
  io::on_root(comm, [&] {
    context.accept_restart();
    io::truncate_csv_rows(context.run_directory / "timeseries.csv", header.timeseries_rows);
  });
  base::Logger::global().info(
      fmt::format("restarting from {} (step {}, t = {:g} s)", file.string(), header.step, header.time));
  return header;
}

bool due(std::int64_t step, std::int64_t every, std::int64_t last)
{
  return step == 0 || step == last || (every > 0 && step % every == 0);
}

} // namespace

std::string field_series_file(const std::string& part)
{
  return "fields_" + part + ".xdmf";
}

std::string stopped_line(std::int64_t step, std::int64_t steps, const std::filesystem::path& file,
                         const std::filesystem::path& run_directory, int signal)
{
  return fmt::format("{}{} of {} (checkpoint {}); continue with: {}",
                     (signal ? "stopped by " + stop_signal_description(signal) + " after step "
                             : std::string("stopped after step ")),
                     step, steps, file.string(), restart_command(launch_command(), run_directory));
}

RunSummary run_time_loop(const RunContext& context, const TimeLoop& loop)
{
  auto& log = base::Logger::global();
  const std::filesystem::path& directory = context.run_directory;
  const std::int64_t steps = loop.steps;
  const bool fields = loop.fields_every >= 0;
  FieldSeries series;
  if (fields) {
    io::create_directories_on_root(loop.comm, directory / "fields");
    for (const std::string& part : loop.field_parts)
      series.try_emplace(part, loop.comm, directory / field_series_file(part), part);
  }
  const io::Checkpoints checkpoints(loop.comm, directory, loop.checkpoints);
  std::int64_t first_step = 0, rows = 0;
  if (context.restart) {
    const io::CheckpointHeader header = restart(checkpoints, context, loop.comm, steps, loop.restore);
    first_step = header.step;
    rows = header.timeseries_rows;
    // Each series goes on from the checkpoint in the file the interrupted run left.
    for (auto& [part, part_series] : series) part_series.resume(loop.time(first_step));
  }
  io::CsvWriter csv; // rank 0's; a failure to open it reaches every rank
  io::on_root(loop.comm, [&] {
    csv = io::CsvWriter(directory / "timeseries.csv", loop.columns, context.restart, loop.units);
  });
  auto outputs = [&](std::int64_t step) {
    if (due(step, loop.record_every, steps) ||
        (loop.record_also_every > 0 && step % loop.record_also_every == 0)) {
      const std::vector<double> row = loop.row(step);
      // Rank 0's row; a failure to write it (a full disk) reaches every rank.
      io::on_root(loop.comm, [&] { csv.write_row(row); });
      ++rows;
    }
    if (fields && due(step, loop.fields_every, steps)) loop.write_fields(series, step);
  };
  auto save = [&](std::int64_t step) {
    if (loop.before_save) loop.before_save();
    return checkpoints.write({step, loop.time(step), rows}, loop.save);
  };
  std::optional<StepDiagnostics> diagnostics;
  if (loop.figures) diagnostics.emplace(loop.comm, directory, loop.figures(), context.restart, first_step);
  auto agreed_signal = [&] { return loop.stop_signal ? loop.stop_signal() : agreed_stop_signal(loop.comm); };

  RunSummary summary;
  if (!context.restart) outputs(0);
  std::int64_t last_step =
      context.stop_after_steps > 0 ? std::min(steps, first_step + context.stop_after_steps) : steps;
  int stop_signal = 0;
  std::filesystem::path saved; // the checkpoint of the step just taken, if it wrote one
  log.begin_steps(first_step, last_step);
  for (std::int64_t n = first_step + 1; n <= last_step; ++n) {
    loop.advance(n);
    const std::optional<StepFigures> figures = loop.figures ? std::optional(loop.figures()) : std::nullopt;
    outputs(n);
    const double t = loop.time(n), end = loop.end_time;
    if (diagnostics) {
      log.progress({n, steps, t, end, diagnostics->write(static_cast<long>(n), t, *figures)});
    } else if (n % loop.progress_every == 0) {
      log.progress({n, steps, t, end, ""});
    }
    if (loop.after_step) loop.after_step(n, summary);
    saved.clear();
    if (checkpoints.due(n, steps)) saved = save(n);
    // SIGINT/SIGTERM (app/stop_signal.hpp): every rank stops after this step.
    if (n < steps && n % loop.stop_check_every == 0 && (stop_signal = agreed_signal()) != 0) {
      last_step = n;
      break;
    }
  }
  log.finish_progress();
  if (last_step < steps) {
    const std::string line =
        stopped_line(last_step, steps, saved.empty() ? save(last_step) : saved, directory, stop_signal);
    if (stop_signal == 0) {
      summary.lines.push_back(line);
    } else {
      summary.stopped = line;
      summary.exit_code = exit_code_of_signal(stop_signal);
    }
  }
  if (loop.finish)
    loop.finish(summary, last_step == steps, series.empty() ? 0 : series.begin()->second.steps());
  return summary;
}

} // namespace ibvalve::app
