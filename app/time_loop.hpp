#pragma once
// The one time loop of every run model (fluid, ibfe, aortic-valve, lumped). A model sets itself up, then
// hands the loop its hooks: how to take a step, the row of timeseries.csv, its field snapshots, its part
// of a checkpoint, the figures of diagnostics.csv, what to do after a step (a cycle's report) and at the
// end. The loop does the rest the same way for all (docs/runs.md):
//  - --restart: reads the newest checkpoint (the model's restore hook), records the case, cuts
//    timeseries.csv and diagnostics.csv back to the checkpoint's step and goes on from there;
//  - timeseries.csv (rank 0 writes; a failure reaches every rank), a row at step 0, every
//    `record_every` steps, at every multiple of `record_also_every` and at the last;
//  - field snapshots in fields/ with an XDMF series per part of the model (fields_fluid.xdmf,
//    fields_structure.xdmf), at step 0, every `fields_every` steps and at the last;
//  - diagnostics.csv and the progress line;
//  - checkpoints (checkpoint.every), --stop-after-steps, and a stop by SIGINT/SIGTERM, which leave a
//    checkpoint and say how to continue.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <mpi.h>

#include "app/model.hpp"
#include "app/step_diagnostics.hpp"
#include "io/checkpoint.hpp"
#include "io/hdf5.hpp"
#include "io/xdmf.hpp"

namespace ibvalve::app {

/// The XDMF series of a run's field snapshots by part ("fluid", "structure"): each part its own file,
/// <run>/fields_<part>.xdmf, so that ParaView opens each as a dataset of its own.
using FieldSeries = std::map<std::string, io::XdmfTimeSeries>;

/// "fields_<part>.xdmf": the file of a part's series, relative to the run folder.
std::string field_series_file(const std::string& part);

struct TimeLoop {
  /// The ranks that take part: the run's communicator, or MPI_COMM_SELF for a model rank 0 runs alone.
  MPI_Comm comm = MPI_COMM_WORLD;
  std::int64_t steps = 1; // the run's last step
  double end_time = 0.0;  // the simulated time after the last step, s (the progress line's)
  io::CheckpointSettings checkpoints;

  std::vector<std::string> columns, units; // timeseries.csv's header and units line
  std::int64_t record_every = 1;
  /// A row also at every multiple of this (a cardiac cycle's steps: its report then has the cycle's
  /// last instant, whatever record_every); 0: none.
  std::int64_t record_also_every = 0;
  /// Field snapshots every this many steps, and at the first and the last step; 0: only those two;
  /// negative: none (no fields/ folder, no XDMF files).
  std::int64_t fields_every = -1;
  /// The parts of the snapshots, each with its series (FieldSeries).
  std::vector<std::string> field_parts{"fluid"};
  std::int64_t progress_every = 1;   // the progress line's update
  std::int64_t stop_check_every = 1; // the ranks' agreement on a stop signal

  /// The simulated time after `step` steps, s.
  std::function<double(std::int64_t step)> time;
  /// Takes step `step` (1, 2, ...). Throws RunError when the run goes wrong.
  std::function<void(std::int64_t step)> advance;
  /// The row of timeseries.csv at step `step` (collective; rank 0's is written).
  std::function<std::vector<double>(std::int64_t step)> row;
  /// Writes the snapshot of step `step` and adds it to the series of each of its parts (collective).
  /// Needed when fields_every >= 0.
  std::function<void(FieldSeries& series, std::int64_t step)> write_fields;
  /// The model's part of a checkpoint, and reading it back (collective over `comm`).
  std::function<void(io::Hdf5File&)> save;
  std::function<void(const io::Hdf5File&)> restore;
  /// Before each checkpoint (e.g. the FFTW plans beside it); may be empty.
  std::function<void()> before_save;
  /// The step's figures for diagnostics.csv and the progress line; empty: no diagnostics.csv.
  std::function<StepFigures()> figures;
  /// After step `step`'s outputs, before its checkpoint (a cycle's report); may be empty.
  std::function<void(std::int64_t step, RunSummary& summary)> after_step;
  /// The stop signal the ranks agree on (app/stop_signal.hpp); empty: agreed_stop_signal(comm).
  std::function<int()> stop_signal;
  /// The summary's closing lines; `finished` is false after a stop, `snapshots` the field snapshots of
  /// the series (each part has them all). May be empty.
  std::function<void(RunSummary& summary, bool finished, std::size_t snapshots)> finish;
};

/// Runs `loop` from step 0 (or from the checkpoint `ibvalve run` chose, on --restart) to its last step,
/// or fewer with --stop-after-steps or a stop signal. Collective over loop.comm. InputError before
/// anything is written when a restart has nothing to continue.
RunSummary run_time_loop(const RunContext& context, const TimeLoop& loop);

/// The summary line of a run stopped at `step` with checkpoint `file`: by --stop-after-steps, or by
/// `signal` (SIGINT, SIGTERM) when it is not 0.
std::string stopped_line(std::int64_t step, std::int64_t steps, const std::filesystem::path& file,
                         const std::filesystem::path& run_directory, int signal = 0);

} // namespace ibvalve::app
