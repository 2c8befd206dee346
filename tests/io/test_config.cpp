// Case files are checked against a schema: each kind of bad input gives one InputError line that
// names the file, the line and the key; a good file gives every key, defaults filled in, in CGS.
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <map>
#include <string>

#include <gtest/gtest.h>
#include <mpi.h>

#include "base/errors.hpp"
#include "base/units.hpp"
#include "io/config.hpp"
#include "io/recorded_config.hpp"

namespace ibvalve::io {
namespace {

Schema example_schema()
{
  Schema boundary;
  boundary.add_string("face", "box face").required().choices({"x-", "x+", "y-", "y+", "z-", "z+"});
  boundary.add_string("type", "condition")
      .defaults(std::string("no-slip"))
      .choices({"no-slip", "traction", "periodic"});
  boundary.add_real("pressure", "normal traction").unit("mmHg").defaults(0.0);

  Schema s;
  s.add_string("model", "what to run").required().choices({"fluid", "lumped"});
  s.add_real("fluid.density", "fluid density").unit("g/mL").defaults(1.0).positive();
  s.add_real("fluid.viscosity", "dynamic viscosity")
      .unit("cP")
      .defaults(4.0)
      .positive()
      .typical(1.0, 20.0, "blood is 3.5 to 4 cP");
  s.add_integer_list("grid.cells", "cells per direction")
      .size(3)
      .defaults(std::vector<std::int64_t>{16, 16, 16})
      .at_least(2);
  s.add_real_list("grid.lengths", "box size")
      .unit("cm")
      .size(3)
      .defaults(std::vector<double>{1.0, 1.0, 1.0})
      .positive();
  s.add_real("time.dt", "time step").unit("s").required().positive().example(1e-3);
  s.add_integer("time.steps", "number of steps").defaults(std::int64_t{10}).at_least(1);
  s.add_boolean("output.fields", "write fields").defaults(true);
  s.retire("output.fields_every", "replaced by output.fields (whether to write fields)");
  s.add_string("mesh.file", "a mesh file").file(true);
  s.add_real("windkessel.compliance", "C").unit("mL/mmHg").defaults(1.75).positive();
  s.add_table_list("fluid.boundary", boundary, "boundary conditions");
  s.add_string("fibers.rule", "fiber rule").defaults(std::string("FD1")).choices({"FD1", "FD2"});
  s.add_string_list("tether.surfaces", "tethered surfaces").defaults(std::vector<std::string>{});
  s.add_real_table("law.parameters", "named parameters").at_least(0.0);
  s.add_string("wk.preset", "named parameters").defaults(std::string("typeA")).choices({"none", "typeA"});
  s.add_real("wk.compliance", "C")
      .unit("mL/mmHg")
      .positive()
      .preset("wk.preset", [](const std::string& name) {
        return name == "typeA" ? std::optional<Value>(1.75 * *units::to_cgs("mL/mmHg")) : std::nullopt;
      });
  s.add_real("wk.distal_pressure", "P_d").unit("mmHg").preset("wk.preset", [](const std::string& name) {
    return name == "typeA" ? std::optional<Value>(0.0) : std::nullopt;
  });
  return s;
}

class CaseFile {
 public:
  explicit CaseFile(const std::string& text)
  {
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    static int counter = 0;
    path_ = std::filesystem::temp_directory_path() /
            (fmt::format("ibvalve_config_{}_{}_{}.toml", ::getpid(), rank, counter++));
    std::ofstream(path_) << text;
  }
  ~CaseFile() { std::filesystem::remove(path_); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

std::string load_error(const std::string& text)
{
  CaseFile file(text);
  try {
    Config::load(file.path(), example_schema());
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
    EXPECT_EQ(message.rfind(file.path().string(), 0), 0u) << "starts with the file name: " << message;
    return message.substr(file.path().string().size());
  }
  ADD_FAILURE() << "no error for:\n" << text;
  return "";
}

TEST(Config, ValidFileGivesEveryKeyInCgs)
{
  CaseFile file(
      "model = \"fluid\"\n[fluid]\nviscosity = 3.5\n[time]\ndt = 1e-3\n[[fluid.boundary]]\nface = \"x-\"\n"
      "type = \"traction\"\npressure = 120\n");
  const Config c = Config::load(file.path(), example_schema());
  EXPECT_DOUBLE_EQ(c.real("fluid.viscosity"), 3.5 * units::cP);
  EXPECT_DOUBLE_EQ(c.real("fluid.density"), 1.0);
  EXPECT_DOUBLE_EQ(c.real("time.dt"), 1e-3);
  EXPECT_EQ(c.integer("time.steps"), 10);
  EXPECT_EQ(c.integers("grid.cells"), (std::vector<std::int64_t>{16, 16, 16}));
  EXPECT_DOUBLE_EQ(c.real("windkessel.compliance"), 1.75 * units::mL / units::mmHg);
  EXPECT_FALSE(c.has("mesh.file"));
  const auto boundaries = c.tables("fluid.boundary");
  ASSERT_EQ(boundaries.size(), 1u);
  EXPECT_EQ(boundaries[0].string("face"), "x-");
  EXPECT_DOUBLE_EQ(boundaries[0].real("pressure"), 120 * units::mmHg);
  EXPECT_EQ(c.where("fluid.viscosity"), file.path().string() + ":3");
}

TEST(Config, ResolvedFileReadsBackToTheSameValues)
{
  CaseFile file("model = \"lumped\"\n[time]\ndt = 2e-4\n[[fluid.boundary]]\nface = \"z+\"\n");
  const Config c = Config::load(file.path(), example_schema());
  CaseFile resolved(c.resolved_toml());
  const Config again = Config::load(resolved.path(), example_schema());
  EXPECT_EQ(again.string("model"), "lumped");
  EXPECT_DOUBLE_EQ(again.real("time.dt"), 2e-4);
  EXPECT_DOUBLE_EQ(again.real("fluid.viscosity"), c.real("fluid.viscosity"));
  EXPECT_EQ(again.tables("fluid.boundary")[0].string("type"), "no-slip");
  EXPECT_NE(c.resolved_toml().find("viscosity = 4.0  # [cP]"), std::string::npos) << c.resolved_toml();
}

TEST(Config, ARunFoldersFileNamesItsFilesRelativeToItself)
{
  // The case names a mesh beside it; the resolved file written into a run folder two levels down names
  // it from there, holds no absolute path, and read from the run folder finds the same file.
  const auto top =
      std::filesystem::temp_directory_path() / fmt::format("ibvalve_config_paths_{}", ::getpid());
  std::filesystem::create_directories(top / "runs" / "a");
  std::ofstream(top / "valve.msh") << "mesh\n";
  std::ofstream(top / "case.toml") << "model = \"fluid\"\n[time]\ndt = 1e-3\n[mesh]\nfile = \"valve.msh\"\n";
  const Config c = Config::load(top / "case.toml", example_schema());
  const std::string written = c.resolved_toml(top / "runs" / "a");
  EXPECT_NE(written.find("file = '../../valve.msh'"), std::string::npos) << written;
  EXPECT_NE(written.find("Read from ../../case.toml"), std::string::npos) << written;
  EXPECT_EQ(written.find(top.string()), std::string::npos) << written;
  std::ofstream(top / "runs" / "a" / "config.toml") << written;
  const Config again = Config::load(top / "runs" / "a" / "config.toml", example_schema());
  EXPECT_TRUE(std::filesystem::equivalent(again.path("mesh.file"), top / "valve.msh"));
  // Without a folder (a checkpoint's record of the case), paths are absolute.
  EXPECT_NE(c.resolved_toml().find((top / "valve.msh").string()), std::string::npos);
  std::filesystem::remove_all(top);
}

TEST(Config, ARecordedConfigReadsBackInShortestNumbersWithUnits)
{
  CaseFile file(
      "model = \"fluid\"\n[time]\ndt = 0.6\n[grid]\nlengths = [0.1, 2.0, 3e-05]\n[wk]\npreset = \"typeA\"\n");
  const Config c = Config::load(file.path(), example_schema());
  CaseFile resolved(c.resolved_toml() + "[extra]\nnegative_zero = -0.0  # [mmHg] a sign that is not there\n");
  std::map<std::string, RecordedEntry> entries;
  for (const RecordedEntry& e : read_recorded_config(resolved.path())) entries[e.key] = e;
  EXPECT_EQ(entries.at("time.dt").value, "0.6");
  EXPECT_EQ(entries.at("time.dt").unit, "s");
  EXPECT_EQ(entries.at("grid.lengths").value, "[0.1, 2, 3e-05]");
  EXPECT_EQ(entries.at("grid.lengths").unit, "cm");
  EXPECT_EQ(entries.at("time.steps").value, "10");
  EXPECT_EQ(entries.at("time.steps").unit, "");
  EXPECT_EQ(entries.at("model").value, "'fluid'");
  EXPECT_EQ(entries.at("wk.compliance").value, "1.75"); // written by the preset ("# from wk.preset = ...")
  EXPECT_EQ(entries.at("wk.compliance").unit, "mL/mmHg");
  EXPECT_EQ(entries.at("extra.negative_zero").value, "0");
  EXPECT_EQ(entries.at("extra.negative_zero").unit, "mmHg");
}

TEST(Config, CommandLineOverridesReplaceFileValues)
{
  CaseFile file("model = \"fluid\"\n[time]\ndt = 1e-3\n");
  const std::vector<std::string> overrides{"time.dt = 5e-4", "fluid.viscosity=2"};
  const Config c = Config::load(file.path(), example_schema(), overrides);
  EXPECT_DOUBLE_EQ(c.real("time.dt"), 5e-4);
  EXPECT_DOUBLE_EQ(c.real("fluid.viscosity"), 2 * units::cP);
}

struct BadCase {
  const char* what;
  const char* text;
  const char* expected; // the message after the file name
};

// Each bad case file and the exact message it must give (after "<file>").
const BadCase bad_cases[] = {
    {"unknown key, with a suggestion", "model = \"fluid\"\n[fluid]\nviscosty = 4\n[time]\ndt = 1\n",
     ":3: fluid.viscosty: unknown key (did you mean 'fluid.viscosity'?)"},
    {"unknown section", "model = \"fluid\"\n[time]\ndt = 1\n[solver]\nrtol = 1\n",
     ":4: solver: unknown table"},
    {"misspelt table", "model = \"fluid\"\n[time]\ndt = 1\n[fluuid]\nviscosity = 4\n",
     ":4: fluuid: unknown table (did you mean 'fluid'?)"},
    {"misspelt table of a dotted key", "model = \"fluid\"\nfluuid.viscosity = 4\n[time]\ndt = 1\n",
     ":2: fluuid: unknown table (did you mean 'fluid'?)"},
    {"misspelt table list", "model = \"fluid\"\n[time]\ndt = 1\n[[fluid.boundry]]\nface = \"x-\"\n",
     ":4: fluid.boundry: unknown key (did you mean 'fluid.boundary'?)"},
    {"wrong type: string for a number", "model = \"fluid\"\n[time]\ndt = \"small\"\n",
     ":3: time.dt: expected a number, got 'small'"},
    {"wrong type: real for an integer", "model = \"fluid\"\n[time]\ndt = 1\nsteps = 2.5\n",
     ":4: time.steps: expected an integer, got 2.5"},
    {"wrong type: number for a boolean", "model = \"fluid\"\n[time]\ndt = 1\n[output]\nfields = 1\n",
     ":5: output.fields: expected true or false, got 1"},
    {"negative viscosity", "model = \"fluid\"\n[fluid]\nviscosity = -0.5\n[time]\ndt = 1\n",
     ":3: fluid.viscosity: -0.5 is out of range (must be > 0 cP)"},
    {"zero time step", "model = \"fluid\"\n[time]\ndt = 0\n",
     ":3: time.dt: 0 is out of range (must be > 0 s)"},
    {"not one of the choices", "model = \"sph\"\n[time]\ndt = 1\n",
     ":1: model: \"sph\" is not one of the allowed values: fluid, lumped"},
    {"missing required key", "model = \"fluid\"\n", ":1: time.dt: missing required key (time step)"},
    {"list of the wrong length", "model = \"fluid\"\n[time]\ndt = 1\n[grid]\ncells = [8, 8]\n",
     ":5: grid.cells: expected 3 values, got 2"},
    {"list element out of range", "model = \"fluid\"\n[time]\ndt = 1\n[grid]\ncells = [8, 1, 8]\n",
     ":5: grid.cells[1]: 1 is out of range (must be >= 2)"},
    {"missing file", "model = \"fluid\"\n[time]\ndt = 1\n[mesh]\nfile = \"no-such-valve.msh\"\n",
     ":5: mesh.file: no such file '"},
    {"bad entry in a table list",
     "model = \"fluid\"\n[time]\ndt = 1\n[[fluid.boundary]]\nface = \"x-\"\ntype = \"slip\"\n",
     ":6: fluid.boundary[0].type: \"slip\" is not one of the allowed values: no-slip, traction, periodic"},
    {"missing key in a table list", "model = \"fluid\"\n[time]\ndt = 1\n[[fluid.boundary]]\npressure = 3\n",
     ":4: fluid.boundary[0].face: missing required key (box face)"},
    {"TOML syntax error", "model = \"fluid\"\n[time]\ndt = = 1\n", ":3: TOML syntax error: "},
    {"infinite value", "model = \"fluid\"\n[time]\ndt = inf\n", ":3: time.dt: must be a finite number"},
    {"a retired key names its replacement", "model = \"fluid\"\n[time]\ndt = 1\n[output]\nfields_every = 5\n",
     ":5: output.fields_every: replaced by output.fields (whether to write fields)"},
};

TEST(Config, EachBadInputGivesItsOwnOneLineMessage)
{
  for (const BadCase& bad : bad_cases) {
    SCOPED_TRACE(bad.what);
    const std::string message = load_error(bad.text);
    EXPECT_EQ(message.rfind(bad.expected, 0), 0u)
        << "got:      " << message << "\nexpected: " << bad.expected;
  }
}

TEST(Config, ARetiredKeyIsNoKeyOfTheListAndStaysRetiredInACopy)
{
  const Schema schema = example_schema();
  const Schema copy(schema);
  ASSERT_NE(copy.retired("output.fields_every"), nullptr);
  EXPECT_EQ(*copy.retired("output.fields_every"), "replaced by output.fields (whether to write fields)");
  EXPECT_EQ(copy.retired("output.fields"), nullptr);
  EXPECT_EQ(schema.markdown().find("fields_every"), std::string::npos);
  Schema twice = schema;
  EXPECT_THROW(twice.retire("output.fields", "a key still read"), std::logic_error);
}

TEST(Config, ATableOfNamedNumbersKeepsTheNamesAndReadsBack)
{
  CaseFile file(
      "model = \"fluid\"\n[time]\ndt = 1e-3\n[law]\nparameters = { mu = 1.5, k2 = 57, a_1 = 0.0 }\n");
  const Config c = Config::load(file.path(), example_schema());
  const std::vector<std::pair<std::string, double>> expected{{"a_1", 0.0}, {"k2", 57.0}, {"mu", 1.5}};
  EXPECT_EQ(c.named_reals("law.parameters"), expected);
  EXPECT_EQ(c.where("law.parameters.k2"), file.path().string() + ":5");
  EXPECT_NE(c.resolved_toml().find("parameters = { a_1 = 0.0, k2 = 57, mu = 1.5 }"), std::string::npos)
      << c.resolved_toml();
  CaseFile resolved(c.resolved_toml());
  EXPECT_EQ(Config::load(resolved.path(), example_schema()).named_reals("law.parameters"), expected);
  // Each entry is a number in the key's range, named in the error.
  EXPECT_EQ(load_error("model = \"fluid\"\n[time]\ndt = 1\n[law]\nparameters = { mu = \"x\" }\n"),
            ":5: law.parameters.mu: expected a number, got 'x'");
  EXPECT_EQ(load_error("model = \"fluid\"\n[time]\ndt = 1\n[law]\nparameters = { mu = -1.0 }\n")
                .rfind(":5: law.parameters.mu: -1 is out of range", 0),
            0u);
  EXPECT_EQ(load_error("model = \"fluid\"\n[time]\ndt = 1\n[law]\nparameters = 3\n"),
            ":5: law.parameters: expected a table of numbers ({ name = number, ... }), got 3");
}

TEST(Config, MissingCaseFileIsAnInputError)
{
  EXPECT_THROW(Config::load("/nonexistent/case.toml", example_schema()), InputError);
}

TEST(Config, BadOverrideNamesTheCommandLine)
{
  CaseFile file("model = \"fluid\"\n[time]\ndt = 1\n");
  const std::vector<std::string> overrides{"time.dt"};
  try {
    Config::load(file.path(), example_schema(), overrides);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()), "command line: --set time.dt: expected key=value");
  }
}

Config load_with(const std::string& text, const std::vector<std::string>& overrides)
{
  CaseFile file(text);
  return Config::load(file.path(), example_schema(), overrides);
}

std::string override_error(const std::vector<std::string>& overrides)
{
  try {
    load_with("model = \"fluid\"\n[time]\ndt = 1\n", overrides);
  } catch (const InputError& error) {
    return error.what();
  }
  ADD_FAILURE() << "no error for --set " << overrides.front();
  return "";
}

TEST(Config, OverrideOfAStringKeyTakesABareWord)
{
  const std::string text = "model = \"fluid\"\n[time]\ndt = 1\n";
  EXPECT_EQ(load_with(text, {"fibers.rule=FD2"}).string("fibers.rule"), "FD2");
  EXPECT_EQ(load_with(text, {"fibers.rule=\"FD2\""}).string("fibers.rule"), "FD2");
  EXPECT_EQ(load_with(text, {"fibers.rule='FD2'"}).string("fibers.rule"), "FD2");
  EXPECT_EQ(load_with(text, {"model=lumped"}).string("model"), "lumped");
  EXPECT_EQ(load_with(text, {"tether.surfaces=[tube_outer, \"tube, inlet\"]"}).strings("tether.surfaces"),
            (std::vector<std::string>{"tube_outer", "tube, inlet"}));
  EXPECT_EQ(load_with(text, {"tether.surfaces=tube_outer"}).strings("tether.surfaces"),
            (std::vector<std::string>{"tube_outer"}));
}

TEST(Config, AFileGivenOnTheCommandLineIsNamedFromTheWorkingFolder)
{
  // The case file lies in the temporary folder, the mesh in the working folder: --set names it as the
  // shell does, and the case holds it absolute.
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  const std::string name = fmt::format("ibvalve_set_path_{}_{}.msh", ::getpid(), rank);
  std::ofstream(name) << "mesh\n";
  const Config c = load_with("model = \"fluid\"\n[time]\ndt = 1\n", {"mesh.file=" + name});
  EXPECT_EQ(c.path("mesh.file"), std::filesystem::absolute(name).lexically_normal());
  EXPECT_EQ(c.string("mesh.file"), std::filesystem::absolute(name).lexically_normal().string());
  std::filesystem::remove(name);
  EXPECT_NE(
      override_error({"mesh.file=" + name}).find("no such file '" + std::filesystem::absolute(name).string()),
      std::string::npos);
}

TEST(Config, AKeyAGivenFileMakesUnusedIsLeftOutOfTheCase)
{
  // A generator's resolution beside the file given instead: no default, a given value set aside with
  // one warning, and nothing of it in the resolved case.
  Schema schema;
  schema.add_string("mesh.file", "a mesh file").file(false);
  schema.add_integer("mesh.cells", "cells of the generated mesh")
      .defaults(std::int64_t{8})
      .unused_with("mesh.file");
  schema.add_real("mesh.radius", "radius").unit("cm").defaults(1.3);
  CaseFile generated("[mesh]\nradius = 2.0\n");
  const Config g = Config::load(generated.path(), schema);
  EXPECT_EQ(g.integer("mesh.cells"), 8);
  EXPECT_NE(g.resolved_toml().find("cells = 8"), std::string::npos);

  CaseFile read("[mesh]\nfile = \"valve.msh\"\ncells = 4\n");
  const Config r = Config::load(read.path(), schema);
  EXPECT_FALSE(r.has("mesh.cells"));
  EXPECT_TRUE(r.has("mesh.radius"));
  ASSERT_EQ(r.warnings().size(), 1u);
  EXPECT_EQ(r.warnings()[0],
            read.path().string() + ":3: mesh.cells: not used with mesh.file (left out of the case)");
  const std::string written = r.resolved_toml();
  EXPECT_EQ(written.find("cells"), std::string::npos) << written;
  EXPECT_NE(written.find("radius = 1.3"), std::string::npos) << written;
  const std::vector<std::string> cells{"mesh.cells=6"};
  EXPECT_EQ(Config::load(read.path(), schema, cells).warnings().size(), 1u);
  EXPECT_NE(schema.markdown().find("cells of the generated mesh (not used with mesh.file)"),
            std::string::npos);
}

TEST(Config, BareWordForANumberNamesTheKeyAndTheType)
{
  EXPECT_EQ(override_error({"fluid.viscosity=abc"}),
            "command line (--set fluid.viscosity=abc):1: fluid.viscosity: expected a number, got 'abc'");
  EXPECT_EQ(override_error({"output.fields=FD2"}),
            "command line (--set output.fields=FD2):1: output.fields: expected true or false, got 'FD2'");
  EXPECT_EQ(override_error({"fibers.rule=FD3"}), "command line (--set fibers.rule=FD3):1: fibers.rule: "
                                                 "\"FD3\" is not one of the allowed values: FD1, FD2");
  EXPECT_EQ(override_error({"grid.cells=[8, 8"}).rfind("command line: --set grid.cells=[8, 8: ", 0), 0u)
      << "a broken list stays a syntax error";
}

TEST(Config, MisspeltTableOnTheCommandLineGetsASuggestion)
{
  EXPECT_EQ(override_error({"fluuid.viscosity=4"}),
            "command line (--set fluuid.viscosity=4):1: fluuid: unknown table (did you mean 'fluid'?)");
}

TEST(Config, ValueOffByAUnitSystemIsWarnedAbout)
{
  CaseFile file("model = \"fluid\"\n[fluid]\nviscosity = 0.004\n[time]\ndt = 1\n");
  const Config c = Config::load(file.path(), example_schema());
  ASSERT_EQ(c.warnings().size(), 1u);
  EXPECT_EQ(c.warnings()[0],
            file.path().string() +
                ":3: fluid.viscosity: 0.004 cP is outside the typical 1 to 20 cP (blood is 3.5 to 4 cP)");
  EXPECT_TRUE(
      load_with("model = \"fluid\"\n[fluid]\nviscosity = 3.5\n[time]\ndt = 1\n", {}).warnings().empty());
  EXPECT_EQ(load_with("model = \"fluid\"\n[time]\ndt = 1\n", {"fluid.viscosity=4000"}).warnings().size(), 1u);
}

TEST(Config, ResolvedFileWritesShortestNumbersAndPresetValues)
{
  const Config c = load_with("model = \"fluid\"\n[time]\ndt = 2e-5\n[grid]\nlengths = [0.1, 0.2, 0.3]\n", {});
  const std::string text = c.resolved_toml();
  EXPECT_NE(text.find("\ndt = 2e-05  #"), std::string::npos) << text;
  EXPECT_NE(text.find("\nlengths = [0.1, 0.2, 0.3]  #"), std::string::npos) << text;
  EXPECT_EQ(text.find("0000000"), std::string::npos) << text;
  EXPECT_NE(text.find("\ncompliance = 1.75  # from wk.preset = \"typeA\"; [mL/mmHg] C"), std::string::npos)
      << text;
  EXPECT_NE(text.find("\ndistal_pressure = 0.0  # from wk.preset"), std::string::npos)
      << "zero, not -0.0: " << text;
  CaseFile resolved(text);
  const Config again = Config::load(resolved.path(), example_schema());
  EXPECT_EQ(again.real("time.dt"), c.real("time.dt"));
  EXPECT_EQ(again.real("wk.compliance"), 1.75 * *units::to_cgs("mL/mmHg")) << "exactly the preset's value";
  EXPECT_EQ(again.reals("grid.lengths"), c.reals("grid.lengths"));

  const Config none = load_with("model = \"fluid\"\n[time]\ndt = 1\n[wk]\npreset = \"none\"\n", {});
  EXPECT_NE(none.resolved_toml().find("# compliance = (not set)"), std::string::npos) << none.resolved_toml();
}

TEST(Config, SkeletonIsACaseFile)
{
  const Schema schema = example_schema();
  const std::vector<std::pair<std::string, Value>> fixed{{"model", std::string("lumped")}};
  const std::string text = schema.toml_skeleton("# a skeleton\n", fixed);
  EXPECT_EQ(text.rfind("# a skeleton\nmodel = 'lumped'", 0), 0u) << text;
  EXPECT_NE(text.find("\ndt = 0.001  # REQUIRED"), std::string::npos) << text;
  EXPECT_NE(text.find("\n# [[fluid.boundary]]"), std::string::npos) << text;
  CaseFile file(text);
  const Config c = Config::load(file.path(), schema);
  EXPECT_EQ(c.string("model"), "lumped");
  EXPECT_DOUBLE_EQ(c.real("fluid.viscosity"), 4.0 * units::cP);
  EXPECT_FALSE(c.has("mesh.file"));
}

TEST(Config, SchemaRejectsUnknownUnitsAndDuplicateKeys)
{
  Schema s;
  EXPECT_THROW(s.add_real("a", "a").unit("furlong"), std::logic_error);
  EXPECT_THROW(s.add_real("a", "again"), std::logic_error);
}

TEST(Config, MarkdownListsEveryKey)
{
  const Schema schema = example_schema();
  const std::string md = schema.markdown();
  for (const auto& spec : schema.keys())
    EXPECT_NE(md.find("`" + spec->key + "`"), std::string::npos) << spec->key;
  EXPECT_NE(md.find("`fluid.boundary[].face`"), std::string::npos);
}

} // namespace
} // namespace ibvalve::io
