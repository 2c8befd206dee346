#pragma once
// The time loop of the `ibfe` run model, shared by its runs on one grid level (app/ibfe_model.cpp) and on
// nested levels (app/ibfe_nested_run.cpp): restart from the newest checkpoint, timeseries.csv (t, volume,
// volume change, largest node speed and displacement, the fluid's kinetic energy), field snapshots every
// `output_every` steps and at the end, diagnostics.csv, checkpoints, --stop-after-steps, and the closing
// summary.
#include <functional>
#include <string>

#include "app/model.hpp"
#include "app/step_diagnostics.hpp"
#include "fe/mesh.hpp"
#include "ib/ibfe.hpp"
#include "io/checkpoint.hpp"
#include "io/hdf5.hpp"
#include "io/xdmf.hpp"

namespace ibvalve::app {

/// What the loop needs of the fluid, which it does not otherwise see.
struct IbfeFluidHooks {
  std::function<double()> kinetic_energy;
  /// Writes the snapshot of step n (fluid and structure) and adds it to the series (collective).
  std::function<void(io::XdmfTimeSeries& series, long step)> write_fields;
  /// The fluid's part of a checkpoint, and reading it back (before the structure's).
  std::function<void(io::Hdf5File&)> save;
  std::function<void(const io::Hdf5File&)> restore;
  /// Appended to the summary's timing line (e.g. solver iterations); may be empty.
  std::function<std::string()> solver_summary;
  /// The fluid's figures of the last step of `dt` for diagnostics.csv and the progress line
  /// (fluid_step_figures). Collective.
  std::function<StepFigures(double dt)> step_figures;
};

struct IbfeLoopSettings {
  double end = 0.0, dt = 0.0;
  long output_every = 1;
  io::CheckpointSettings checkpoints;
};

/// Runs `ibfe` (already set up with its starting displacement) from t = 0, or from the run folder's
/// newest checkpoint on --restart, to `settings.end`. Collective.
RunSummary run_ibfe_loop(const RunContext& context, ib::IbfeIntegrator& ibfe, const fe::Mesh& mesh,
                         const IbfeLoopSettings& settings, const IbfeFluidHooks& fluid);

} // namespace ibvalve::app
