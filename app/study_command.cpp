// `ibvalve study STUDY.toml`: runs the cases a study file lists (one base case file plus `--set`-style
// overrides per case, e.g. the six material/fiber combinations W1FD1 ... W3FD2 of the paper's Table 7),
// then compares them (`ibvalve compare`). Either here, one after the other on the ranks this command
// was started on, or, with --jobs, as shell lines to submit as separate MPI jobs.
//
// Study file:
//   base = "default.toml"            # case file of every case (relative to the study file)
//   output = "runs/study"            # each case runs in <output>/<case name>; comparison in
//   <output>/comparison set = ["time.cycles=1"]          # overrides for every case (optional)
//   leave_out = ["fit_error"]        # ranking criteria the comparison leaves out (optional)
//   [[case]]
//   name = "W1FD1"
//   set = ["structure.material.preset=\"zhu2021-W1\""]   # this case's overrides (after the common ones)
//   file = "other.toml"              # optional: a different case file for this case
//   [[uncertainty]]                  # optional: a source of numerical uncertainty
//   name = "time step"
//   set = ["time.step=2e-5"]         # every case runs again with these overrides after its own
//   shared = true                    # optional: the source's error is common to the cases
//
// Each source runs every case once more in <output>/uncertainty/<source>/<case>; a metric's standard
// uncertainty from a source is |variant - case| (the change a second step, grid, kernel or partition
// makes: docs/runs.md, "Studies"), combined over the sources as sqrt(sum u_s^2) and written to
// <output>/<case>/uncertainty.json, which the case's report (rewritten) and the comparison read. A shared
// source also keeps its signed shift, variant - case, so that the comparison judges a difference between
// two cases by how much the source changes the difference itself (docs/hemodynamics.md, "Comparison").
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <iostream>
#include <memory>
#include <set>
#include <sstream>

#include <petscsys.h>

#include "app/commands.hpp"
#include "base/errors.hpp"
#include "base/logger.hpp"
#include "hemodynamics/compare.hpp"
#include "hemodynamics/report.hpp"
#include "io/collective.hpp"
#include "io/config.hpp"
#include "io/files.hpp"

namespace ibvalve::app {

namespace {

struct StudyOptions {
  std::filesystem::path study_file;
  std::filesystem::path output; // overrides the study's `output`
  bool jobs = false;
  int ranks = 1;
  bool overwrite = false;
  bool collect = false; // run nothing: gather the folders --jobs ran
};

struct StudyCase {
  std::string name;
  std::filesystem::path case_file;
  std::vector<std::string> overrides;
};

struct UncertaintySource {
  std::string name;
  std::vector<std::string> overrides;
  bool shared = false; // the error is common to the cases: their shifts are kept signed
};

struct Study {
  std::filesystem::path output;
  std::vector<std::string> leave_out; // ranking criteria the comparison leaves out
  std::vector<StudyCase> cases;
  std::vector<UncertaintySource> sources;
};

/// The folder of a case's variant for an uncertainty source: <output>/uncertainty/<source>/<case>,
/// with the source's name made a folder name (spaces and slashes as '_').
std::string variant_folder_name(const UncertaintySource& source)
{
  std::string folder = source.name;
  for (char& ch : folder)
    if (ch == ' ' || ch == '/') ch = '_';
  return folder;
}

std::filesystem::path variant_folder(const Study& study, const UncertaintySource& source, const StudyCase& c)
{
  return study.output / "uncertainty" / variant_folder_name(source) / c.name;
}

/// The case's overrides with the source's after them (the case keeps its name).
std::vector<std::string> variant_overrides(const StudyCase& c, const UncertaintySource& source)
{
  std::vector<std::string> overrides = c.overrides;
  overrides.insert(overrides.end(), source.overrides.begin(), source.overrides.end());
  return overrides;
}

/// One [[case]] of a study file.
struct CaseKeys {
  std::string name;
  std::filesystem::path file;
  std::vector<std::string> set;
};

/// One [[uncertainty]] of a study file.
struct SourceKeys {
  std::string name;
  std::vector<std::string> set;
  bool shared = false;
};

/// A study file's keys (io/key_binder.hpp).
struct StudyKeys {
  std::filesystem::path base;
  std::string output;
  std::vector<std::string> set, leave_out;
  std::vector<CaseKeys> cases;
  std::vector<SourceKeys> sources;
};

void bind(io::KeyBinder& keys, CaseKeys& c)
{
  keys.string("name", "the case's name: its run folder and its name in the comparison", c.name).required();
  keys.path("file", "this case's own case file (default: base)", c.file);
  keys.strings("set", "this case's overrides, after the common ones", c.set)
      .defaults(std::vector<std::string>{});
}

void bind(io::KeyBinder& keys, SourceKeys& u)
{
  keys.string("name", "the source's name (\"time step\", \"grid\"): its folder and its label", u.name)
      .required();
  keys.strings("set", "overrides of the variant every case runs again with, after its own", u.set).required();
  keys.boolean("shared",
               "the source's error is common to the cases (a second grid or step applied to all): each "
               "metric keeps its signed shift, variant - case, and the comparison judges a difference "
               "between two cases by how much the source changes that difference; false = independent",
               u.shared)
      .defaults(false);
}

void bind(io::KeyBinder& keys, StudyKeys& k)
{
  keys.path("base", "case file every case starts from (relative to the study file)", k.base);
  keys.string("output", "folder for the cases (<output>/<name>) and the comparison (<output>/comparison)",
              k.output)
      .defaults(std::string("runs/study"));
  keys.strings("set", "overrides for every case, as with ibvalve run --set", k.set)
      .defaults(std::vector<std::string>{});
  keys.strings("leave_out",
               "ranking criteria (metric keys, e.g. \"fit_error\") the comparison leaves out, as with "
               "ibvalve compare --leave-out",
               k.leave_out)
      .defaults(std::vector<std::string>{});
  keys.tables("case", "the cases, in the order they run", k.cases,
              [](io::KeyBinder& element, CaseKeys& c) { bind(element, c); });
  keys.tables("uncertainty",
              "sources of numerical uncertainty: each reruns every case with its overrides, and "
              "|variant - case| is that source's standard uncertainty of each metric",
              k.sources, [](io::KeyBinder& element, SourceKeys& u) { bind(element, u); });
}

/// A case of the study: its name checked (a folder of the study's own), its file and its overrides.
StudyCase study_case(const io::KeyBinder& keys, const StudyKeys& k, const CaseKeys& c,
                     std::set<std::string>& names)
{
  StudyCase one;
  one.name = c.name;
  // The case runs in <output>/<name>: a name, not a path, and not a folder the study writes itself.
  if (const std::string why = io::folder_name_problem(one.name); !why.empty()) keys.fail(c.name, why);
  if (one.name == "comparison" || one.name == "uncertainty")
    keys.fail(c.name,
              "\"" + one.name + "\" is the study's own folder (the comparison, the uncertainty runs)");
  if (!names.insert(one.name).second) keys.fail(c.name, "\"" + one.name + "\" is listed twice");
  if (keys.has(c.file))
    one.case_file = c.file;
  else if (keys.has(k.base))
    one.case_file = k.base;
  else
    keys.fail(c.file, "the case has no file and the study no base");
  one.overrides = k.set;
  for (const auto& o : c.set) one.overrides.push_back(o);
  one.overrides.push_back("name=\"" + one.name + "\"");
  return one;
}

Study read_study(const StudyOptions& options)
{
  io::Schema schema;
  {
    io::KeyBinder declaring(schema);
    StudyKeys unused;
    bind(declaring, unused);
  }
  const io::Config config = io::Config::load(options.study_file, schema);
  io::KeyBinder keys(config);
  StudyKeys k;
  bind(keys, k);
  Study study;
  study.output = options.output.empty() ? std::filesystem::path(k.output) : options.output;
  if (!keys.has(k.cases)) keys.fail(k.cases, "a study needs at least one [[case]]");
  study.leave_out = k.leave_out;
  if (const std::string why = hemodynamics::check_criteria(study.leave_out); !why.empty())
    keys.fail(k.leave_out, why);
  std::set<std::string> names;
  for (const CaseKeys& c : k.cases) study.cases.push_back(study_case(keys, k, c, names));
  std::set<std::string> sources;
  for (const SourceKeys& u : k.sources) {
    UncertaintySource source{u.name, u.set, u.shared};
    if (source.name.empty()) keys.fail(u.name, "must not be empty");
    if (const std::string why = io::folder_name_problem(variant_folder_name(source)); !why.empty())
      keys.fail(u.name, why);
    if (!sources.insert(source.name).second) keys.fail(u.name, "\"" + source.name + "\" is listed twice");
    if (source.overrides.empty()) keys.fail(u.set, "a source needs at least one override");
    study.sources.push_back(std::move(source));
  }
  return study;
}

std::string quoted(const std::string& word)
{
  std::string q = "'";
  for (char ch : word) q += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return q + "'";
}

int print_jobs(const Study& study, const StudyOptions& options)
{
  const std::string program = std::filesystem::read_symlink("/proc/self/exe").string();
  std::ostringstream out;
  out << "# " << study.cases.size() << " cases of " << options.study_file.string()
      << ": submit each line as a job, then the compare line when all have finished\n";
  std::string runs;
  auto job = [&](const StudyCase& c, const std::filesystem::path& folder,
                 const std::vector<std::string>& overrides) {
    out << "mpiexec -n " << options.ranks << ' ' << quoted(program) << " run "
        << quoted(std::filesystem::absolute(c.case_file).string()) << " -o " << quoted(folder.string())
        << " --overwrite";
    for (const auto& o : overrides) out << " --set " << quoted(o);
    out << '\n';
  };
  for (const auto& c : study.cases) {
    const auto folder = study.output / c.name;
    job(c, folder, c.overrides);
    runs += ' ' + quoted(folder.string());
  }
  for (const auto& source : study.sources)
    for (const auto& c : study.cases) job(c, variant_folder(study, source, c), variant_overrides(c, source));
  if (study.sources.empty()) {
    out << quoted(program) << " compare" << runs << " -o " << quoted((study.output / "comparison").string());
    for (const auto& key : study.leave_out) out << " --leave-out " << quoted(key);
    out << '\n';
  } else // the uncertainties need the study file: collect combines them, rewrites the reports, compares
    out << quoted(program) << " study " << quoted(std::filesystem::absolute(options.study_file).string())
        << " -o " << quoted(study.output.string()) << " --collect\n";
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0) std::cout << out.str() << std::flush;
  return 0;
}

/// Each case's uncertainty.json from its variants, and its report written again with it (rank 0).
void combine_uncertainties(const Study& study)
{
  using hemodynamics::Json;
  for (const StudyCase& c : study.cases) {
    const std::filesystem::path folder = study.output / c.name;
    const hemodynamics::CaseResult nominal = hemodynamics::load_case(folder);
    Json out = Json::object();
    for (const auto& source : study.sources) {
      const hemodynamics::CaseResult variant = hemodynamics::load_case(variant_folder(study, source, c));
      for (const auto& [key, entry] : nominal.metrics.items()) {
        const auto value = [&](const Json& metrics) -> std::optional<double> {
          const auto m = metrics.find(key);
          if (m == metrics.end() || !m->is_object()) return std::nullopt;
          const auto v = m->find("value");
          return v != m->end() && v->is_number() ? std::optional(v->get<double>()) : std::nullopt;
        };
        const auto a = value(nominal.metrics), b = value(variant.metrics);
        if (!a || !b) continue;
        out[key]["sources"][source.name] = std::abs(*b - *a);
        if (source.shared) out[key]["shared"][source.name] = *b - *a;
      }
    }
    for (auto& [key, entry] : out.items()) {
      double sum = 0.0;
      for (const auto& [name, u] : entry["sources"].items()) sum += u.get<double>() * u.get<double>();
      entry["uncertainty"] = std::sqrt(sum);
    }
    io::write_file_atomically(folder / "uncertainty.json", out.dump(2) + "\n");
    const hemodynamics::RecordedReport recorded = hemodynamics::recorded_report(folder);
    hemodynamics::ReportOptions report;
    report.settings = recorded.report.metrics;
    report.run_period = recorded.period;
    report.plots = recorded.report.plots;
    report.cycle_plots = recorded.report.cycle_plots;
    report.templates = recorded.report.templates;
    hemodynamics::write_report(folder, report);
    base::Logger::global().info(fmt::format("study: {}: uncertainties from {} source(s) in {}", c.name,
                                            study.sources.size(), (folder / "uncertainty.json").string()));
  }
}

int run_study(const StudyOptions& options, const PetscArguments& petsc)
{
  const Study study = read_study(options);
  if (options.jobs) return print_jobs(study, options);
  auto& log = base::Logger::global();
  std::vector<std::filesystem::path> folders;
  auto run_one = [&](const StudyCase& c, const std::filesystem::path& folder,
                     const std::vector<std::string>& overrides) {
    RunOptions run;
    run.case_file = c.case_file;
    run.output = folder;
    run.overrides = overrides;
    run.overwrite = options.overwrite;
    return run_case(run, petsc);
  };
  for (std::size_t i = 0; i < study.cases.size(); ++i) {
    const StudyCase& c = study.cases[i];
    folders.push_back(study.output / c.name);
    if (options.collect) continue;
    log.info(fmt::format("study: case {} of {}: {}", i + 1, study.cases.size(), c.name));
    // A case stopped by SIGINT/SIGTERM stops the study with it.
    if (const int code = run_one(c, folders.back(), c.overrides); code != 0) return code;
  }
  if (!options.collect)
    for (const auto& source : study.sources)
      for (const auto& c : study.cases) {
        log.info(fmt::format("study: uncertainty '{}': {}", source.name, c.name));
        if (const int code = run_one(c, variant_folder(study, source, c), variant_overrides(c, source));
            code != 0)
          return code;
      }
  if (!study.sources.empty()) io::on_root(PETSC_COMM_WORLD, [&] { combine_uncertainties(study); });
  log.info(fmt::format("study: comparing {} cases", folders.size()));
  hemodynamics::ComparisonOptions compare;
  compare.leave_out = study.leave_out;
  return compare_runs(folders, study.output / "comparison", compare);
}

} // namespace

void add_study_command(CLI::App& app, CommandAction& action)
{
  auto options = std::make_shared<StudyOptions>();
  CLI::App* sub = app.add_subcommand(
      "study", "Run the cases a study file lists (base case + overrides each), then compare them");
  sub->add_option("study", options->study_file, "the study file (TOML)")->required();
  sub->add_option("-o,--output", options->output,
                  "folder for the cases and the comparison (default: the study's output)")
      ->check(non_empty_path);
  sub->add_flag("--jobs", options->jobs,
                "print one `mpiexec ... ibvalve run` line per case and the compare line, run nothing");
  sub->add_option("--ranks", options->ranks, "ranks per case in the --jobs lines")
      ->check(CLI::PositiveNumber);
  sub->add_flag("--overwrite", options->overwrite, "replace existing case folders' contents");
  sub->add_flag("--collect", options->collect,
                "run nothing: combine the uncertainties of the folders the --jobs lines ran, rewrite the "
                "cases' reports, compare")
      ->excludes("--jobs");
  sub->callback([options, &action] {
    action = [options](const PetscArguments& petsc) { return run_study(*options, petsc); };
  });
}

} // namespace ibvalve::app
