#pragma once
// The kinds of run `ibvalve run` knows (`model = "..."` in a case file) and how each is set up.
//
// A model adds its keys to the case schema, then `prepare` reads the validated configuration and
// checks everything a schema cannot (files, consistent grids, ...), throwing InputError before any
// output exists. Only then is the run folder created and `run` called, so bad input never leaves a
// half-written run behind.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <mpi.h>

#include "app/resource_estimate.hpp"
#include "base/logger.hpp"
#include "io/config.hpp"
#include "io/key_binder.hpp"

namespace ibvalve::app {

struct RunContext {
  MPI_Comm comm = MPI_COMM_WORLD;
  std::filesystem::path run_directory;
  bool restart = false; // continue from the run folder's last checkpoint (io/checkpoint.hpp)
  /// Stop after this many steps of this invocation, with a checkpoint (0 = run to the end); lets a run
  /// fit a batch job's wall-time limit and tests stop a run midway.
  std::int64_t stop_after_steps = 0;
  /// On restart: the checkpoint to continue from, chosen and checked by `ibvalve run` (the newest
  /// intact one of this case, io::Checkpoints::latest).
  std::filesystem::path checkpoint;
  /// On restart: records the case with its --set overrides in config.toml. Called on rank 0 only once
  /// the model has accepted the checkpoint (restored it and found steps left to take), so a rejected
  /// override never reaches config.toml. Throws InputError.
  std::function<void()> accept_restart = [] {};
};

/// What a finished run tells the user: where its output and its report went.
struct RunSummary {
  std::vector<std::string> lines;
  /// A run stopped by SIGINT or SIGTERM (app/stop_signal.hpp): the line saying where it stopped and how
  /// to continue, printed whatever the log level, and the exit code 128 + the signal's number.
  std::string stopped;
  int exit_code = 0;
};

class PreparedRun {
 public:
  virtual ~PreparedRun() = default;
  virtual RunSummary run(const RunContext& context) = 0;
  /// What the prepared run is, in a few words (`ibvalve check`'s line): "" when the model says nothing
  /// beyond its name.
  virtual std::string summary() const { return ""; }
  /// The memory estimate (app/resource_estimate.hpp) the run logs at its start; "" for none.
  const std::string& memory_line() const { return memory_line_; }

 protected:
  std::string memory_line_;
};

/// A model's add_schema when its keys are one bound section: `bind(io::KeyBinder&, Keys&)` (found by
/// argument-dependent lookup beside Keys) run against the schema.
template <class Keys>
void add_bound_schema(io::Schema& schema)
{
  Keys unused;
  io::KeyBinder keys(schema);
  bind(keys, unused);
}

struct Model {
  std::string name;
  std::string description;
  std::function<void(io::Schema&)> add_schema;
  std::function<std::unique_ptr<PreparedRun>(const io::Config&)> prepare;
};

/// Every model, in the order `ibvalve run --help` lists them.
const std::vector<Model>& models();
const Model* find_model(const std::string& name);

/// fluid.density (g/mL, with the typical range that catches a value in kg/m^3) bound to `rho`
/// (io/key_binder.hpp), as every model that has a fluid declares it; `doc` says which fluid.
void bind_fluid_density(io::KeyBinder& keys, double& rho, const std::string& doc);
/// fluid.viscosity (cP) of a general fluid, water to syrup, defaulting to `default_cP`, bound to `mu`: the
/// fluid and ibfe models (the aortic valve's is blood's, with a narrower typical range).
void bind_fluid_viscosity(io::KeyBinder& keys, double& mu, double default_cP);

/// The keys every case has, whatever its model (io/key_binder.hpp): what it runs, its name and run
/// folder, the log, its PETSc options and the memory limit.
struct CommonKeys {
  std::string model, name;
  std::string output_directory; ///< no default: runs/<name>
  base::LogLevel log_level = base::LogLevel::normal;
  double progress_interval = 0.0; ///< s
  std::string petsc_options;
  MemoryKeys memory;
};

/// Declares (a Schema binder) or reads (a Config binder) the keys every case has.
void bind(io::KeyBinder& keys, CommonKeys& k);

/// The keys every case has (bind(keys, CommonKeys&)) and the retired spellings every case is refused.
io::Schema common_schema();
/// common_schema() plus the model's own keys.
io::Schema case_schema(const Model& model);

} // namespace ibvalve::app
