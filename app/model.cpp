#include "app/model.hpp"

#include "app/output_keys.hpp"
#include "app/resource_estimate.hpp"

#include <vector>

namespace ibvalve::app {

Model lumped_model();       // app/lumped_model.cpp
Model ibfe_model();         // app/ibfe_model.cpp
Model fluid_model();        // app/fluid_model.cpp
Model aortic_valve_model(); // app/aortic_valve_model.cpp

namespace {
std::vector<std::string> model_names()
{
  std::vector<std::string> names;
  for (const Model& m : models()) names.push_back(m.name);
  return names;
}
} // namespace

const std::vector<Model>& models()
{
  // Each model registers itself here as its folder provides it.
  static const std::vector<Model> all = [] {
    std::vector<Model> list;
    // A build of a subset of the folders (IBVALVE_FOLDERS) has the models whose folders it has.
#if IBVALVE_HAVE_WINDKESSEL && IBVALVE_HAVE_CIRCULATION && IBVALVE_HAVE_HEMODYNAMICS
    list.push_back(lumped_model());
#endif
#if IBVALVE_HAVE_IB
    list.push_back(ibfe_model());
#endif
#if IBVALVE_HAVE_FLUID
    list.push_back(fluid_model());
#endif
#if IBVALVE_HAVE_IB && IBVALVE_HAVE_FIBERS && IBVALVE_HAVE_DRIVERS && IBVALVE_HAVE_HEMODYNAMICS
    list.push_back(aortic_valve_model());
#endif
    return list;
  }();
  return all;
}

const Model* find_model(const std::string& name)
{
  for (const Model& m : models())
    if (m.name == name) return &m;
  return nullptr;
}

void bind(io::KeyBinder& keys, CommonKeys& k)
{
  keys.string("model", "what to run", k.model).required().choices(model_names());
  keys.string("name", "a name for the case, used for the default run folder", k.name).defaults(std::string{});
  keys.string("output.directory", "run folder (relative to the working directory); default runs/<case name>",
              k.output_directory);
  keys.choice("log.level", "how much to print", k.log_level,
              {{"quiet", base::LogLevel::quiet},
               {"normal", base::LogLevel::normal},
               {"verbose", base::LogLevel::verbose}})
      .defaults(std::string("normal"));
  keys.real("log.progress_interval", "seconds between progress lines when not on a terminal",
            k.progress_interval)
      .unit("s")
      .defaults(10.0)
      .positive();
  keys.string("petsc.options",
              "PETSc options of ibvalve's solvers (e.g. \"-fluid_stokes_ksp_type gmres\"; "
              "the rule: docs/design.md); command-line options win",
              k.petsc_options)
      .defaults(std::string{});
  bind(keys, k.memory);
}

io::Schema common_schema()
{
  io::Schema s;
  io::KeyBinder keys(s);
  CommonKeys unused;
  bind(keys, unused);
  retire_output_spellings(s);
  return s;
}

void bind_fluid_density(io::KeyBinder& keys, double& rho, const std::string& doc)
{
  keys.real("fluid.density", doc, rho)
      .unit("g/mL")
      .defaults(1.0)
      .positive()
      .typical(0.5, 2.0, "blood is 1.06 g/mL, water 1; 1000 times more is a value in kg/m^3");
}

void bind_fluid_viscosity(io::KeyBinder& keys, double& mu, double default_cP)
{
  keys.real("fluid.viscosity", "dynamic viscosity", mu)
      .unit("cP")
      .defaults(default_cP)
      .non_negative()
      .typical(0.1, 1000.0, "water is 1 cP, blood 3.5 to 4 cP; 1000 times less is a value in Pa s");
}

io::Schema case_schema(const Model& model)
{
  io::Schema s = common_schema();
  model.add_schema(s);
  return s;
}

} // namespace ibvalve::app
