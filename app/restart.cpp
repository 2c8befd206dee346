#include "app/restart.hpp"

#include <algorithm>

#include <mpi.h>

#include "app/stop_signal.hpp"
#include "io/collective.hpp"
#include "io/errors.hpp"
#include "io/logger.hpp"

namespace ibvalve::app {

io::CheckpointHeader restart_from_latest(const io::Checkpoints& checkpoints, const RunContext& context,
                                         std::int64_t steps,
                                         const std::function<void(const io::Hdf5File&)>& restore)
{
  const std::filesystem::path& file = context.checkpoint;
  if (file.empty())
    throw InputError(context.run_directory.string() + ": no checkpoint to restart from (checkpoint.every)");
  const io::CheckpointHeader header = checkpoints.read(file, restore);
  if (header.step >= steps)
    throw InputError(file.string() + ": the checkpoint is at step " + std::to_string(header.step) +
                     " but the run now ends at step " + std::to_string(steps) +
                     ": nothing to continue (lengthen the run with --set)");
  // Rank 0 alone writes config.toml and timeseries.csv; the others wait, so that nobody appends before
  // the cut, and learn of any failure there.
  io::on_root(context.comm, [&] {
    context.accept_restart();
    io::truncate_csv_rows(context.run_directory / "timeseries.csv", header.timeseries_rows);
  });
  io::Logger::global().info("restarting from " + file.string() + " (step " + std::to_string(header.step) +
                            ", t = " + std::to_string(header.time) + " s)");
  return header;
}

std::int64_t last_step_of_invocation(const RunContext& context, std::int64_t first_step, std::int64_t steps)
{
  return context.stop_after_steps > 0 ? std::min(steps, first_step + context.stop_after_steps) : steps;
}

std::string stopped_line(std::int64_t step, std::int64_t steps, const std::filesystem::path& file,
                         const std::filesystem::path& run_directory, int signal)
{
  return (signal ? "stopped by " + signal_name(signal) + " after step "
                 : std::string("stopped after step ")) +
         std::to_string(step) + " of " + std::to_string(steps) + " (checkpoint " + file.string() +
         "); continue with: ibvalve run --restart " + run_directory.string();
}

void add_stop(RunSummary& summary, std::int64_t step, std::int64_t steps, const std::filesystem::path& file,
              const std::filesystem::path& run_directory, int signal)
{
  const std::string line = stopped_line(step, steps, file, run_directory, signal);
  if (signal == 0) {
    summary.lines.push_back(line);
    return;
  }
  summary.stopped = line;
  summary.exit_code = exit_code_of_signal(signal);
}

} // namespace ibvalve::app
