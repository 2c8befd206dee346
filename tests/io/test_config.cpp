// Case files are checked against a schema: each kind of bad input gives one InputError line that
// names the file, the line and the key; a good file gives every key, defaults filled in, in CGS.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <mpi.h>

#include "io/config.hpp"
#include "io/errors.hpp"
#include "io/units.hpp"

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
  s.add_real("fluid.viscosity", "dynamic viscosity").unit("cP").defaults(4.0).positive();
  s.add_integer_list("grid.cells", "cells per direction")
      .size(3)
      .defaults(std::vector<std::int64_t>{16, 16, 16})
      .at_least(2);
  s.add_real_list("grid.lengths", "box size")
      .unit("cm")
      .size(3)
      .defaults(std::vector<double>{1.0, 1.0, 1.0})
      .positive();
  s.add_real("time.dt", "time step").unit("s").required().positive();
  s.add_integer("time.steps", "number of steps").defaults(std::int64_t{10}).at_least(1);
  s.add_boolean("output.fields", "write fields").defaults(true);
  s.add_string("mesh.file", "a mesh file").file(true);
  s.add_real("windkessel.compliance", "C").unit("mL/mmHg").defaults(1.75).positive();
  s.add_table_list("fluid.boundary", boundary, "boundary conditions");
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
            ("ibvalve_config_" + std::to_string(::getpid()) + "_" + std::to_string(rank) + "_" +
             std::to_string(counter++) + ".toml");
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
    {"unknown section", "model = \"fluid\"\n[time]\ndt = 1\n[solver]\nrtol = 1\n", ":4: solver: unknown key"},
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
