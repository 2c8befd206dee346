// `ibvalve run CASE.toml`: validate the case, create the run folder, run the model.
#include <algorithm>
#include <array>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <petscsys.h>

#include "app/case_petsc_options.hpp"
#include "app/commands.hpp"
#include "app/model.hpp"
#include "app/step_schedule.hpp"
#include "app/stop_signal.hpp"
#include "base/build_info.hpp"
#include "base/errors.hpp"
#include "base/logger.hpp"
#include "io/checkpoint.hpp"
#include "io/collective.hpp"
#include "io/files.hpp"
#include "io/petsc_check.hpp"

namespace ibvalve::app {

std::string PetscArguments::joined() const
{
  std::string s;
  for (const auto& option : options) s += (s.empty() ? "" : " ") + option;
  return s;
}

namespace {

/// The spec of `key` in the case schema of the model `table` names, or of any model when it names none
/// (so that --set reads a bare word for a string key, io::apply_overrides).
const io::KeySpec* case_key(const toml::table& table, std::string_view key)
{
  static const io::Schema common = common_schema();
  if (const io::KeySpec* spec = common.find(key)) return spec;
  static const std::vector<std::pair<std::string, io::Schema>> own = [] {
    std::vector<std::pair<std::string, io::Schema>> list;
    for (const Model& m : models()) {
      io::Schema s;
      m.add_schema(s);
      list.emplace_back(m.name, std::move(s));
    }
    return list;
  }();
  const std::string named = table.get("model") ? table.get("model")->value_or(std::string{}) : std::string{};
  for (const auto& [name, schema] : own)
    if (name == named) return schema.find(key);
  for (const auto& [name, schema] : own)
    if (const io::KeySpec* spec = schema.find(key)) return spec;
  return nullptr;
}

/// "case.toml:3" for a node of the case (or of a --set override, whose source names the command line).
std::string where(const toml::source_region& source, const std::filesystem::path& file)
{
  const std::string name = source.path && !source.path->empty() ? *source.path : file.string();
  return source.begin.line > 0 ? fmt::format("{}:{}", name, source.begin.line) : name;
}

/// The case's model, read before any other key: which keys are valid depends on it, so a missing,
/// misspelt or unknown `model` is reported as such (with the models there are), and not as the first
/// of the model's own keys that the common keys lack.
const Model& case_model(const toml::table& table, const std::filesystem::path& file)
{
  std::string names;
  for (const Model& m : models()) names += (names.empty() ? "" : ", ") + m.name;
  if (names.empty()) names = "(this build has no models)";
  const toml::node* node = table.get("model");
  if (!node) {
    // A top-level string key a letter or two from "model" (modle, mdoel, models) is the model key misspelt.
    for (auto&& [key, value] : table)
      if (value.is_string() && key.str() != "name" && io::edit_distance(key.str(), "model") <= 2)
        throw InputError(where(key.source(), file) + ": " + std::string(key.str()) +
                         ": unknown key (did you mean 'model'?)");
    throw InputError(where(table.source(), file) + ": model: missing required key (what to run: " + names +
                     ")");
  }
  if (!node->is_string()) {
    std::ostringstream shown;
    node->visit([&](const auto& v) { shown << v; });
    throw InputError(where(node->source(), file) + ": model: expected a string (one of " + names + "), got " +
                     shown.str().substr(0, 40));
  }
  const std::string name = *node->value<std::string>();
  if (const Model* model = find_model(name)) return *model;
  std::string hint;
  std::size_t best = 4;
  for (const Model& m : models())
    if (const std::size_t d = io::edit_distance(m.name, name); d < best) {
      best = d;
      hint = " (did you mean '" + m.name + "'?)";
    }
  throw InputError(where(node->source(), file) + ": model: \"" + name +
                   "\" is not one of the allowed values: " + names + hint);
}

io::Config load_case(const RunOptions& options)
{
  toml::table table = io::parse_toml_file(options.case_file);
  io::apply_overrides(table, options.overrides, [&](std::string_view key) { return case_key(table, key); });
  const Model& model = case_model(table, options.case_file);
  io::Config config = io::Config::validate(std::move(table), options.case_file, case_schema(model));
  // The name is the default run folder's (runs/<name>): a name, not a path. Empty: the case file's name.
  io::KeyBinder keys(config);
  CommonKeys common;
  bind(keys, common);
  if (!common.name.empty())
    if (const std::string why = io::folder_name_problem(common.name); !why.empty())
      keys.fail(common.name, why);
  return config;
}

std::filesystem::path run_directory(const RunOptions& options, const io::Config& config)
{
  if (!options.restart.empty()) return options.restart;
  if (!options.output.empty()) return options.output;
  io::KeyBinder keys(config);
  CommonKeys common;
  bind(keys, common);
  if (keys.has(common.output_directory)) return common.output_directory;
  std::string name = common.name;
  if (name.empty()) name = options.case_file.stem().string();
  return std::filesystem::path("runs") / name;
}

/// What a run writes into its folder (docs/runs.md). --overwrite removes these, and nothing else, before
/// the new run starts: no checkpoint of the old run can be pruned with the new run's or continued by
/// --restart, and no field file, plan or report of the old run passes for the new run's (fields.xdmf:
/// the one series of fluid and structure that older builds wrote).
constexpr std::array<const char*, 13> run_outputs{
    "checkpoints",           "fftw_wisdom", "fields",      "fields_fluid.xdmf",
    "fields_structure.xdmf", "fields.xdmf", "report",      "timeseries.csv",
    "diagnostics.csv",       "log.txt",     "config.toml", "run.json",
    "extra_metrics.json"};

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
    io::write_file_atomically(directory / "config.toml", config.resolved_toml(directory));
  } catch (const std::exception& e) {
    throw InputError(directory.string() + ": cannot write the run folder (" + e.what() + ")");
  }
}

/// Records in run.json where the run came from (rank 0): the case file, this ibvalve's version and
/// commit, when it started and on how many ranks; a restart appends when, by which build and on how
/// many ranks to "restarts". The report carries it (hemodynamics/report.hpp, "provenance").
void write_run_record(const std::filesystem::path& directory, const std::filesystem::path& case_file,
                      int ranks, bool restart)
{
  const std::filesystem::path file = directory / "run.json";
  nlohmann::ordered_json record;
  const nlohmann::ordered_json build{
      {"at", base::utc_now()}, {"ibvalve", base::version()}, {"commit", base::commit()}, {"ranks", ranks}};
  if (restart && std::filesystem::exists(file)) {
    try {
      record = nlohmann::ordered_json::parse(io::read_text_file(file));
    } catch (const nlohmann::json::exception& e) {
      throw InputError(file.string() + ": not the run record ibvalve writes (" + e.what() + ")");
    }
    record["restarts"].push_back(build);
  } else {
    record = {{"case_file", std::filesystem::absolute(case_file).lexically_normal().string()},
              {"ibvalve", base::version()},
              {"commit", base::commit()},
              {"started", build["at"]},
              {"ranks", ranks},
              {"restarts", nlohmann::ordered_json::array()}};
  }
  try {
    io::write_file_atomically(file, record.dump(2) + "\n");
  } catch (const std::exception& e) {
    throw InputError(directory.string() + ": cannot write the run folder (" + e.what() + ")");
  }
}

/// Keeps the run's warnings in run.json's "warnings" (rank 0), after those of its earlier invocations,
/// from now until the end of this invocation: each time one is logged, and once for those of the case
/// (base/logger.hpp). The report shows them (hemodynamics/report.hpp).
class WarningRecord {
 public:
  explicit WarningRecord(const std::filesystem::path& directory) : file_(directory / "run.json")
  {
    auto& log = base::Logger::global();
    if (!log.is_root()) return;
    try {
      earlier_ = nlohmann::ordered_json::parse(io::read_text_file(file_)).value("warnings", earlier_);
    } catch (const std::exception&) {
      // No record to add to: log.txt keeps the warnings.
      return;
    }
    log.set_warning_record([this](const std::vector<std::string>& warnings) { write(warnings); });
    try {
      write(log.warnings());
    } catch (const std::exception&) {
      // As Logger::warn: a record that cannot be written leaves log.txt's.
    }
  }
  ~WarningRecord() { base::Logger::global().set_warning_record(nullptr); }
  WarningRecord(const WarningRecord&) = delete;
  WarningRecord& operator=(const WarningRecord&) = delete;

 private:
  void write(const std::vector<std::string>& warnings) const
  {
    nlohmann::ordered_json record = nlohmann::ordered_json::parse(io::read_text_file(file_));
    nlohmann::ordered_json all = earlier_;
    for (const std::string& w : warnings)
      if (std::find(all.begin(), all.end(), w) == all.end()) all.push_back(w);
    record["warnings"] = all;
    io::write_file_atomically(file_, record.dump(2) + "\n");
  }

  std::filesystem::path file_;
  nlohmann::ordered_json earlier_ = nlohmann::ordered_json::array();
};

/// PETSc options that no solver read, usually a misspelt name or solver prefix, which PETSc passes over
/// in silence: one warning line naming them (those of the case file and those after --).
void warn_unused_petsc_options()
{
  PetscInt count = 0;
  char** names = nullptr;
  char** values = nullptr;
  PETSC_CHECK(PetscOptionsLeftGet(nullptr, &count, &names, &values));
  std::string list;
  for (PetscInt i = 0; i < count; ++i) list += std::string(list.empty() ? "" : " ") + "-" + names[i];
  PETSC_CHECK(PetscOptionsLeftRestore(nullptr, &count, &names, &values));
  if (!list.empty())
    base::Logger::global().warn(
        "PETSc options not used: " + list +
        " (check the name and the solver prefix: `ibvalve --help` lists the prefixes)");
}

} // namespace

PreparedCase prepare_case(const RunOptions& options, const PetscArguments& petsc)
{
  auto& log = base::Logger::global();
  if (options.quiet) log.set_level(base::LogLevel::quiet);
  if (options.verbose) log.set_level(base::LogLevel::verbose);
  log.set_strict(options.strict);
  log.clear_warnings();
  io::Config config = load_case(options);
  io::KeyBinder keys(config);
  CommonKeys common;
  bind(keys, common);
  if (!options.quiet && !options.verbose) log.set_level(common.log_level);
  log.set_progress_interval(common.progress_interval);
  // Values far outside their key's typical range (another unit system?) are warned about; the run goes on.
  for (const std::string& warning : config.warnings()) log.warn(warning);
  // Case options first, then the command line's, so that the command line wins; those of the case that
  // read or write files are refused first (the command line's are the user's own).
  check_case_petsc_options(keys, common.petsc_options);
  PETSC_CHECK(PetscOptionsInsertString(nullptr, common.petsc_options.c_str()));
  PETSC_CHECK(PetscOptionsInsertString(nullptr, petsc.joined().c_str()));
  const Model* model = find_model(common.model);
  PreparedCase prepared{std::move(config), model, nullptr};
  prepared.run = model->prepare(prepared.config);
  return prepared;
}

int run_case(RunOptions options, const PetscArguments& petsc)
{
  if (!options.restart.empty() && !options.case_file.empty())
    throw InputError("command line: give either a case file or --restart RUN_DIR, not both");
  if (options.restart.empty() && options.case_file.empty())
    throw InputError("command line: a case file is required (or --restart RUN_DIR)");
  if (options.stop_after_steps < 0)
    throw InputError(fmt::format(
        "command line: --stop-after-steps {}: must be at least 0 (0, like leaving it out, runs to the end)",
        options.stop_after_steps));
  // A restart reads the case as the run folder recorded it (every default written out).
  if (!options.restart.empty()) {
    if (!std::filesystem::is_regular_file(options.restart / "config.toml"))
      throw InputError(options.restart.string() + ": not a run folder (no config.toml to restart from)");
    options.case_file = options.restart / "config.toml";
  }
  auto& log = base::Logger::global();
  log.start_clock();
  const PreparedCase prepared_case = prepare_case(options, petsc);
  const io::Config& config = prepared_case.config;
  const Model& model = *prepared_case.model;
  PreparedRun* prepared = prepared_case.run.get();

  const std::filesystem::path directory = run_directory(options, config);
  int size = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  // A restart continues the newest intact checkpoint of this very case (a torn or corrupt one is passed
  // over, one of another case refused): chosen here, before anything is written.
  std::filesystem::path checkpoint;
  if (!options.restart.empty()) {
    io::KeyBinder keys(config);
    io::CheckpointSettings checkpoints;
    io::bind(keys, checkpoints);
    checkpoints.case_record = io::case_record(config);
    const auto file = io::Checkpoints(PETSC_COMM_WORLD, directory, checkpoints).latest();
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
      write_run_record(directory, options.case_file, size, false);
    });
  }
  log.open_file(directory / "log.txt");
  const WarningRecord warning_record(directory);
  log.info(fmt::format("ibvalve {}: {}{}{} on {}{}", base::version(), model.name,
                       (options.restart.empty() ? " run of " : " restart of "), options.case_file.string(),
                       size, (size == 1 ? " rank" : " ranks")));
  log.info("run folder: " + directory.string());
  if (!prepared->memory_line().empty()) log.info(prepared->memory_line());

  RunContext context{PETSC_COMM_WORLD, directory, !options.restart.empty(), options.stop_after_steps,
                     checkpoint};
  // Overrides given with --restart (e.g. more cycles) become part of the run's recorded case, once the
  // model has accepted the checkpoint.
  context.accept_restart = [&] {
    write_config(directory, config);
    write_run_record(directory, options.case_file, size, true);
  };
  // From here on SIGINT and SIGTERM stop the run with a checkpoint (app/stop_signal.hpp).
  catch_stop_signals();
  const RunSummary summary = prepared->run(context);
  for (const auto& line : summary.lines) log.info(line);
  warn_unused_petsc_options();
  if (!summary.stopped.empty()) {
    log.always(summary.stopped);
    return summary.exit_code;
  }
  log.info("finished in " + base::format_duration(log.wall_seconds()) + "; output in " + directory.string());
  return summary.exit_code;
}

std::string petsc_options_help()
{
  // The prefixes the solvers set (KSPSetOptionsPrefix in fluid/, ib/, fibers/); README lists them too.
  return "PETSc options go after `--` (and in petsc.options); each solver has its prefix:\n"
         "  -fluid_stokes_       Krylov (FGMRES) Stokes solve each step: fluid (not periodic), ibfe\n"
         "                       (fluid.boundary = walls), aortic-valve (one grid)\n"
         "  -fluid_helmholtz_    its viscous (Helmholtz) sub-solve; -fluid_poisson_: its pressure sub-solve\n"
         "  -fluid_fftw_planner  estimate|measure|patient: FFTW plans (fluid, ibfe, aortic-valve)\n"
         "  -nested_pressure_    pressure solve on nested levels (nested.ratios); -nested_velocity_: "
         "viscous\n"
         "  -ib_velocity_mass_   consistent L2 projection to the nodes (ibfe, aortic-valve);\n"
         "                       -ib_force_mass_: the force projection when it differs\n"
         "  -fibers_             fiber Laplace solves (aortic-valve, ibvalve fibers)\n"
         "e.g. ibvalve run case.toml -- -fluid_stokes_ksp_converged_reason  (why each Stokes solve stopped)";
}

void add_run_command(CLI::App& app, CommandAction& action)
{
  auto options = std::make_shared<RunOptions>();
  std::string model_list;
  for (const Model& m : models()) model_list += "\n  " + m.name + ": " + m.description;
  CLI::App* sub = app.add_subcommand("run", "Run a case file (TOML). Models:" + model_list +
                                                "\nTheir keys: ibvalve keys [MODEL].");
  sub->footer(petsc_options_help());
  sub->add_option("case", options->case_file, "the case file (TOML)");
  sub->add_option("--restart", options->restart,
                  "continue the run in this folder from its last checkpoint (its config.toml is the case)");
  sub->add_option(
         "--stop-after-steps", options->stop_after_steps,
         "stop after this many steps, writing a checkpoint (continue with --restart); 0 runs to the end")
      ->check(CLI::Validator(
          [](std::string& value) {
            // Read as written, before the integer conversion, which takes a count beyond int64 silently.
            const long double count = std::strtold(value.c_str(), nullptr);
            return count > max_run_steps ? fmt::format("{}: more than the {:.0e} steps a run takes at most",
                                                       value.substr(0, 40), max_run_steps)
                                         : std::string();
          },
          "N"));
  sub->add_option("-o,--output", options->output, "run folder (default: output.directory or runs/<name>)")
      ->check(non_empty_path);
  sub->add_option(
      "--set", options->overrides,
      "override a key, e.g. --set fluid.viscosity=3.5 or --set fibers.rule=FD2 (a bare word for a "
      "string key; repeatable)");
  sub->add_flag(
      "--overwrite", options->overwrite,
      "replace the run in an existing folder (its config, log, series, fields, checkpoints, report)");
  sub->add_flag("-v,--verbose", options->verbose, "print more");
  sub->add_flag("-q,--quiet", options->quiet, "print only errors");
  sub->add_flag("--strict", options->strict,
                "a warning is an error (exit 2 with its line): a value outside its key's usual range, a step "
                "beyond the stability estimate, an inverted element, a PETSc option no solver read, ...");
  sub->callback([options, &action] {
    action = [options](const PetscArguments& petsc) { return run_case(*options, petsc); };
  });
}

} // namespace ibvalve::app
