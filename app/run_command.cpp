// `ibvalve run CASE.toml`: validate the case, create the run folder, run the model.
#include <array>
#include <filesystem>
#include <sstream>

#include <petscsys.h>

#include "app/commands.hpp"
#include "app/model.hpp"
#include "app/stop_signal.hpp"
#include "app/version.hpp"
#include "io/checkpoint.hpp"
#include "io/collective.hpp"
#include "io/errors.hpp"
#include "io/files.hpp"
#include "io/logger.hpp"
#include "io/petsc_check.hpp"

namespace ibvalve::app {

std::string PetscArguments::joined() const
{
  std::string s;
  for (const auto& option : options) s += (s.empty() ? "" : " ") + option;
  return s;
}

namespace {

io::Config load_case(const RunOptions& options)
{

  toml::table table = io::parse_toml_file(options.case_file);
  io::apply_overrides(table, options.overrides);
  const toml::node* model_node = table.get("model");
  // Validate against the common keys first when the model is missing or unknown, so that the error
  // names the `model` key and lists the models there are.
  const Model* model = nullptr;
  if (model_node && model_node->is_string()) model = find_model(*model_node->value<std::string>());
  if (!model) {
    const std::string where =
        model_node ? options.case_file.string() + ":" + std::to_string(model_node->source().begin.line)
                   : options.case_file.string();
    const std::string name = model_node ? model_node->value_or(std::string{}) : std::string{};
    io::Config::validate(std::move(table), options.case_file, common_schema());
    // Only reached when no model is registered (the schema's choices are then empty).
    throw InputError(where + ": model: \"" + name +
                     "\" is not one of the allowed values: (this build has no models)");
  }
  return io::Config::validate(std::move(table), options.case_file, case_schema(*model));
}

std::filesystem::path run_directory(const RunOptions& options, const io::Config& config)
{
  if (!options.restart.empty()) return options.restart;
  if (!options.output.empty()) return options.output;
  if (config.has("output.directory")) return config.string("output.directory");
  std::string name = config.string("name");
  if (name.empty()) name = options.case_file.stem().string();
  return std::filesystem::path("runs") / name;
}

/// What a run writes into its folder (docs/runs.md). --overwrite removes these, and nothing else, before
/// the new run starts: no checkpoint of the old run can be pruned with the new run's or continued by
/// --restart, and no field file, plan or report of the old run passes for the new run's.
constexpr std::array<const char*, 8> run_outputs{"checkpoints", "fftw_wisdom",    "fields",  "fields.xdmf",
                                                 "report",      "timeseries.csv", "log.txt", "config.toml"};

/// Creates the run folder (rank 0): InputError naming the path when it is not a folder, cannot be
/// created, or holds files and --overwrite was not given; with --overwrite the old run's outputs go.
void prepare_run_folder(const std::filesystem::path& directory, bool overwrite)
{
  try {
    if (std::filesystem::exists(directory) && !std::filesystem::is_directory(directory))
      throw InputError(directory.string() + ": is not a folder (give -o a folder to write the run into)");
    if (std::filesystem::exists(directory) && !std::filesystem::is_empty(directory)) {
      if (!overwrite)
        throw InputError(directory.string() +
                         ": run folder exists and is not empty (give --overwrite, or -o another folder)");
      for (const char* name : run_outputs) std::filesystem::remove_all(directory / name);
    }
    std::filesystem::create_directories(directory);
  } catch (const std::filesystem::filesystem_error& e) {
    throw InputError(directory.string() + ": cannot create the run folder (" + e.code().message() + ")");
  }
}

/// Writes the resolved case into the run folder (rank 0), atomically: InputError naming the folder when
/// it cannot be written.
void write_config(const std::filesystem::path& directory, const io::Config& config)
{
  try {
    io::write_file_atomically(directory / "config.toml", config.resolved_toml());
  } catch (const std::exception& e) {
    throw InputError(directory.string() + ": cannot write the run folder (" + e.what() + ")");
  }
}

} // namespace

int run_case(RunOptions options, const PetscArguments& petsc)
{
  if (!options.restart.empty() && !options.case_file.empty())
    throw InputError("command line: give either a case file or --restart RUN_DIR, not both");
  if (options.restart.empty() && options.case_file.empty())
    throw InputError("command line: a case file is required (or --restart RUN_DIR)");
  if (options.stop_after_steps < 0)
    throw InputError("command line: --stop-after-steps " + std::to_string(options.stop_after_steps) +
                     ": must be at least 0 (0, like leaving it out, runs to the end)");
  // A restart reads the case as the run folder recorded it (every default written out).
  if (!options.restart.empty()) {
    if (!std::filesystem::is_regular_file(options.restart / "config.toml"))
      throw InputError(options.restart.string() + ": not a run folder (no config.toml to restart from)");
    options.case_file = options.restart / "config.toml";
  }
  auto& log = io::Logger::global();
  log.start_clock();
  if (options.quiet) log.set_level(io::LogLevel::quiet);
  if (options.verbose) log.set_level(io::LogLevel::verbose);

  const io::Config config = load_case(options);
  if (!options.quiet && !options.verbose) {
    const std::string level = config.string("log.level");
    log.set_level(level == "quiet"     ? io::LogLevel::quiet
                  : level == "verbose" ? io::LogLevel::verbose
                                       : io::LogLevel::normal);
  }
  log.set_progress_interval(config.real("log.progress_interval"));
  // Case options first, then the command line's, so that the command line wins.
  PETSC_CHECK(PetscOptionsInsertString(nullptr, config.string("petsc.options").c_str()));
  PETSC_CHECK(PetscOptionsInsertString(nullptr, petsc.joined().c_str()));

  const Model& model = *find_model(config.string("model"));
  std::unique_ptr<PreparedRun> prepared = model.prepare(config);

  const std::filesystem::path directory = run_directory(options, config);
  int size = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  // A restart continues the newest intact checkpoint of this very case (a torn or corrupt one is passed
  // over, one of another case refused): chosen here, before anything is written.
  std::filesystem::path checkpoint;
  if (!options.restart.empty()) {
    const auto file =
        io::Checkpoints(PETSC_COMM_WORLD, directory, io::checkpoint_settings_from_config(config)).latest();
    // A model that writes no checkpoints must not silently start over in the folder it was asked to continue.
    if (!file)
      throw InputError(directory.string() +
                       ": no complete checkpoint to restart from (models write them with "
                       "checkpoint.every > 0 or when stopped by --stop-after-steps; the " +
                       model.name + " model may not write any)");
    checkpoint = *file;
  } else {
    // Rank 0 makes the folder; whatever goes wrong there (a path under a file, /proc, a full disk) is an
    // input error that every rank throws, so none waits for the others.
    io::on_root(PETSC_COMM_WORLD, [&] {
      prepare_run_folder(directory, options.overwrite);
      write_config(directory, config);
    });
  }
  log.open_file(directory / "log.txt");
  log.info(std::string("ibvalve ") + version_string + ": " + model.name +
           (options.restart.empty() ? " run of " : " restart of ") + options.case_file.string() + " on " +
           std::to_string(size) + (size == 1 ? " rank" : " ranks"));
  log.info("run folder: " + directory.string());

  RunContext context{PETSC_COMM_WORLD, directory, !options.restart.empty(), options.stop_after_steps,
                     checkpoint};
  // Overrides given with --restart (e.g. more cycles) become part of the run's recorded case, once the
  // model has accepted the checkpoint.
  context.accept_restart = [&] { write_config(directory, config); };
  // From here on SIGINT and SIGTERM stop the run with a checkpoint (app/stop_signal.hpp).
  catch_stop_signals();
  const RunSummary summary = prepared->run(context);
  for (const auto& line : summary.lines) log.info(line);
  if (!summary.stopped.empty()) {
    log.always(summary.stopped);
    return summary.exit_code;
  }
  log.info("finished in " + io::format_duration(log.wall_seconds()) + "; output in " + directory.string());
  return summary.exit_code;
}

void add_run_command(CLI::App& app, CommandAction& action)
{
  auto options = std::make_shared<RunOptions>();
  std::string model_list;
  for (const Model& m : models()) model_list += "\n  " + m.name + ": " + m.description;
  CLI::App* sub = app.add_subcommand("run", "Run a case file (TOML). Models:" + model_list);
  sub->add_option("case", options->case_file, "the case file (TOML)");
  sub->add_option("--restart", options->restart,
                  "continue the run in this folder from its last checkpoint (its config.toml is the case)");
  sub->add_option(
      "--stop-after-steps", options->stop_after_steps,
      "stop after this many steps, writing a checkpoint (continue with --restart); 0 runs to the end");
  sub->add_option("-o,--output", options->output, "run folder (default: output.directory or runs/<name>)");
  sub->add_option("--set", options->overrides,
                  "override a key, e.g. --set fluid.viscosity=0.05 (repeatable)");
  sub->add_flag(
      "--overwrite", options->overwrite,
      "replace the run in an existing folder (its config, log, series, fields, checkpoints, report)");
  sub->add_flag("-v,--verbose", options->verbose, "print more");
  sub->add_flag("-q,--quiet", options->quiet, "print only errors");
  sub->callback([options, &action] {
    action = [options](const PetscArguments& petsc) { return run_case(*options, petsc); };
  });
}

} // namespace ibvalve::app
