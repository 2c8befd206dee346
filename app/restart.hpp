#pragma once
// Checkpoint/restart of the grid-based run models (fluid, ibfe, aortic-valve): the steps they share
// around io/checkpoint.hpp, so each model only says what its state is.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "app/model.hpp"
#include "io/checkpoint.hpp"

namespace ibvalve::app {

/// On `--restart`: reads the checkpoint `ibvalve run` chose (context.checkpoint) through `restore`
/// (collective over the checkpoints' communicator), records the case (context.accept_restart), cuts
/// timeseries.csv back to the rows it had then (rank 0 of `comm`) and logs where the run goes on from.
/// InputError, before anything is written or cut, when there is no checkpoint or it is already at or
/// past the run's last step `steps`.
io::CheckpointHeader restart_from_latest(const io::Checkpoints& checkpoints, const RunContext& context,
                                         std::int64_t steps,
                                         const std::function<void(const io::Hdf5File&)>& restore);

/// The last step of this invocation: `steps` (the run's end), or fewer with --stop-after-steps.
std::int64_t last_step_of_invocation(const RunContext& context, std::int64_t first_step, std::int64_t steps);

/// The summary line of a run stopped at `step` with checkpoint `file`: by --stop-after-steps, or by
/// `signal` (SIGINT, SIGTERM) when it is not 0.
std::string stopped_line(std::int64_t step, std::int64_t steps, const std::filesystem::path& file,
                         const std::filesystem::path& run_directory, int signal = 0);

/// Adds a run's stop at `step` (checkpoint `file`) to its summary: the line, and for a stop by
/// `signal` the exit code 128 + signal.
void add_stop(RunSummary& summary, std::int64_t step, std::int64_t steps, const std::filesystem::path& file,
              const std::filesystem::path& run_directory, int signal);

} // namespace ibvalve::app
