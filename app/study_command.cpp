// `ibvalve study STUDY.toml`: runs the cases a study file lists (one base case file plus `--set`-style
// overrides per case, e.g. the six material/fiber combinations W1FD1 ... W3FD2 of the paper's Table 7),
// then compares them (`ibvalve compare`). Either here, one after the other on the ranks this command
// was started on, or, with --jobs, as shell lines to submit as separate MPI jobs.
//
// Study file:
//   base = "default.toml"            # case file of every case (relative to the study file)
//   output = "runs/study"            # each case runs in <output>/<case name>; comparison in
//   <output>/comparison set = ["time.cycles=1"]          # overrides for every case (optional)
//   [[case]]
//   name = "W1FD1"
//   set = ["structure.material.preset=\"zhu2021-W1\""]   # this case's overrides (after the common ones)
//   file = "other.toml"              # optional: a different case file for this case
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
#include "io/config.hpp"

namespace ibvalve::app {

namespace {

struct StudyOptions {
  std::filesystem::path study_file;
  std::filesystem::path output; // overrides the study's `output`
  bool jobs = false;
  int ranks = 1;
  bool overwrite = false;
};

struct StudyCase {
  std::string name;
  std::filesystem::path case_file;
  std::vector<std::string> overrides;
};

struct Study {
  std::filesystem::path output;
  std::vector<StudyCase> cases;
};

io::Schema study_schema()
{
  io::Schema s;
  s.add_string("base", "case file every case starts from (relative to the study file)").file(true);
  s.add_string("output", "folder for the cases (<output>/<name>) and the comparison (<output>/comparison)")
      .defaults(std::string("runs/study"));
  s.add_string_list("set", "overrides for every case, as with ibvalve run --set")
      .defaults(std::vector<std::string>{});
  io::Schema one;
  one.add_string("name", "the case's name: its run folder and its name in the comparison").required();
  one.add_string("file", "this case's own case file (default: base)").file(true);
  one.add_string_list("set", "this case's overrides, after the common ones")
      .defaults(std::vector<std::string>{});
  s.add_table_list("case", one, "the cases, in the order they run");
  return s;
}

Study read_study(const StudyOptions& options)
{
  const io::Config config = io::Config::load(options.study_file, study_schema());
  Study study;
  study.output = options.output.empty() ? std::filesystem::path(config.string("output")) : options.output;
  if (!config.has("case")) config.fail("case", "a study needs at least one [[case]]");
  const std::vector<std::string> common = config.strings("set");
  std::set<std::string> names;
  for (const io::Config& c : config.tables("case")) {
    StudyCase one;
    one.name = c.string("name");
    if (one.name.empty() || one.name.find('/') != std::string::npos || one.name == "comparison")
      c.fail("name", "must be a non-empty folder name other than \"comparison\"");
    if (!names.insert(one.name).second) c.fail("name", "\"" + one.name + "\" is listed twice");
    if (c.has("file"))
      one.case_file = c.path("file");
    else if (config.has("base"))
      one.case_file = config.path("base");
    else
      c.fail("file", "the case has no file and the study no base");
    one.overrides = common;
    for (const auto& o : c.strings("set")) one.overrides.push_back(o);
    one.overrides.push_back("name=\"" + one.name + "\"");
    study.cases.push_back(std::move(one));
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
  for (const auto& c : study.cases) {
    const auto folder = study.output / c.name;
    out << "mpiexec -n " << options.ranks << ' ' << quoted(program) << " run "
        << quoted(std::filesystem::absolute(c.case_file).string()) << " -o " << quoted(folder.string())
        << " --overwrite";
    for (const auto& o : c.overrides) out << " --set " << quoted(o);
    out << '\n';
    runs += ' ' + quoted(folder.string());
  }
  out << quoted(program) << " compare" << runs << " -o " << quoted((study.output / "comparison").string())
      << '\n';
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0) std::cout << out.str() << std::flush;
  return 0;
}

int run_study(const StudyOptions& options, const PetscArguments& petsc)
{
  const Study study = read_study(options);
  if (options.jobs) return print_jobs(study, options);
  auto& log = base::Logger::global();
  std::vector<std::filesystem::path> folders;
  for (std::size_t i = 0; i < study.cases.size(); ++i) {
    const StudyCase& c = study.cases[i];
    log.info(fmt::format("study: case {} of {}: {}", i + 1, study.cases.size(), c.name));
    RunOptions run;
    run.case_file = c.case_file;
    run.output = study.output / c.name;
    run.overrides = c.overrides;
    run.overwrite = options.overwrite;
    // A case stopped by SIGINT/SIGTERM stops the study with it.
    if (const int code = run_case(run, petsc); code != 0) return code;
    folders.push_back(run.output);
  }
  log.info(fmt::format("study: comparing {} cases", folders.size()));
  return compare_runs(folders, study.output / "comparison", hemodynamics::ComparisonOptions{});
}

} // namespace

void add_study_command(CLI::App& app, CommandAction& action)
{
  auto options = std::make_shared<StudyOptions>();
  CLI::App* sub = app.add_subcommand(
      "study", "Run the cases a study file lists (base case + overrides each), then compare them");
  sub->add_option("study", options->study_file, "the study file (TOML)")->required();
  sub->add_option("-o,--output", options->output,
                  "folder for the cases and the comparison (default: the study's output)");
  sub->add_flag("--jobs", options->jobs,
                "print one `mpiexec ... ibvalve run` line per case and the compare line, run nothing");
  sub->add_option("--ranks", options->ranks, "ranks per case in the --jobs lines")
      ->check(CLI::PositiveNumber);
  sub->add_flag("--overwrite", options->overwrite, "replace existing case folders' contents");
  sub->callback([options, &action] {
    action = [options](const PetscArguments& petsc) { return run_study(*options, petsc); };
  });
}

} // namespace ibvalve::app
