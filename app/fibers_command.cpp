// `ibvalve fibers MESH.msh --rule FD1|FD2 [--leaflet GROUP ...] -o OUT`: rule-based leaflet fibers
// (fibers/rules.hpp) written as OUT/fibers.xdmf + OUT/fibers.h5 (ParaView: the Laplace potential,
// the Dirichlet sets and the fiber per element) and OUT/element_fibers.txt, the file a run reads back.
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <petscsys.h>

#include "app/commands.hpp"
#include "base/errors.hpp"
#include "base/logger.hpp"
#include "fe/gmsh_io.hpp"
#include "fe/mesh_output.hpp"
#include "fibers/rules.hpp"
#include "io/collective.hpp"
#include "io/files.hpp"
#include "io/xdmf.hpp"

namespace ibvalve::app {

namespace {

struct FibersCommandOptions {
  std::filesystem::path mesh;
  std::string rule;
  std::vector<std::string> leaflets;
  std::string n1, n2, tau1, tau2, attachment;
  std::vector<double> axis{0, 0, 0, 0, 0, 1};
  std::filesystem::path output;
  bool overwrite = false;
};

int run_fibers(const FibersCommandOptions& options)
{
  auto& log = base::Logger::global();
  // The rule and the axis come from the command line: its errors say so and name the option.
  fibers::FiberRule rule{};
  try {
    rule = fibers::parse_fiber_rule(options.rule);
  } catch (const InputError&) {
    throw InputError("command line: --rule " + options.rule + ": not a fiber rule (FD1 or FD2)");
  }
  if (options.axis.size() != 6) throw InputError("command line: --axis: give six numbers px,py,pz,dx,dy,dz");
  for (double x : options.axis)
    if (!std::isfinite(x))
      throw InputError(fmt::format("command line: --axis: {} is not a finite number", x));
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  // Rank 0 checks the output folder (and makes it below, once the fields exist); an error there is
  // every rank's, so none waits for rank 0.
  io::on_root(PETSC_COMM_WORLD, [&] {
    if (std::filesystem::exists(options.output) && !std::filesystem::is_directory(options.output))
      throw InputError(options.output.string() + ": is not a folder (give -o a folder to write into)");
    if (std::filesystem::exists(options.output) && !std::filesystem::is_empty(options.output) &&
        !options.overwrite)
      throw InputError(options.output.string() +
                       ": output folder exists and is not empty (give --overwrite)");
  });

  const fe::Mesh mesh = fe::read_msh(options.mesh);
  std::vector<std::string> leaflets = options.leaflets;
  if (leaflets.empty())
    for (const auto& group : mesh.groups())
      if (group.dimension == 3 && group.name.rfind("leaflet", 0) == 0) leaflets.push_back(group.name);
  const bool explicit_selectors =
      !(options.n1 + options.n2 + options.tau1 + options.tau2 + options.attachment).empty();
  if (explicit_selectors && leaflets.size() > 1)
    throw InputError(
        "command line: --n1/--n2/--tau1/--tau2/--attachment apply to one leaflet; with several, name the "
        "groups <leaflet>_n1, <leaflet>_tau1 ... in the mesh");
  std::vector<fibers::LeafletSpec> specs;
  for (const auto& name : leaflets) {
    fibers::LeafletSpec spec;
    spec.group = name;
    specs.push_back(spec);
  }
  if (specs.empty()) specs.emplace_back();
  for (auto& spec : specs) {
    spec.n1 = options.n1;
    spec.n2 = options.n2;
    spec.tau1 = options.tau1;
    spec.tau2 = options.tau2;
    spec.attachment = options.attachment;
    spec.axis_point = fibers::Vec3(options.axis[0], options.axis[1], options.axis[2]);
    spec.axis_direction = fibers::Vec3(options.axis[3], options.axis[4], options.axis[5]);
    if (spec.axis_direction.norm() == 0) throw InputError("command line: --axis: the direction is zero");
  }

  log.info(fmt::format(
      "fibers: {}: {} {} elements, {} nodes; rule {} on {}", options.mesh.string(), mesh.num_elements(),
      mesh.type().name(), mesh.num_nodes(), options.rule,
      (leaflets.empty() ? std::string("the whole mesh") : fmt::format("{} leaflet(s)", leaflets.size()))));
  const fibers::FiberField field = fibers::compute_fibers(mesh, rule, specs, PETSC_COMM_WORLD);

  io::on_root(PETSC_COMM_WORLD, [&] { io::create_output_folder(options.output); });
  std::vector<double> directions;
  std::size_t with_fibers = 0;
  for (const auto& f : field.element_directions) {
    directions.insert(directions.end(), {f[0], f[1], f[2]});
    with_fibers += f.squaredNorm() > 0;
  }
  const std::vector<fe::MeshField> fields{{"potential", io::Center::node, 1, field.potential, "1"},
                                          {"dirichlet", io::Center::node, 1, field.dirichlet, "1"},
                                          {"fiber", io::Center::cell, 3, directions, "1"}};
  io::XdmfTimeSeries series(PETSC_COMM_WORLD, options.output / "fibers.xdmf", "fibers");
  series.add_step(0.0, {fe::write_mesh_fields(PETSC_COMM_WORLD, mesh, options.output / "fibers.h5",
                                              options.output, "fibers", fields)});
  fibers::write_element_fibers(options.output / "element_fibers.txt", field.element_directions,
                               PETSC_COMM_WORLD);
  log.info(fmt::format("fibers: {} of {} elements have a fiber; wrote {} and {}", with_fibers,
                       mesh.num_elements(), (options.output / "fibers.xdmf").string(),
                       (options.output / "element_fibers.txt").string()));
  return 0;
}

} // namespace

void add_fibers_command(CLI::App& app, CommandAction& action)
{
  auto options = std::make_shared<FibersCommandOptions>();
  CLI::App* sub = app.add_subcommand(
      "fibers",
      "Leaflet fiber fields from Laplace problems (FD1: corner points n1/n2; FD2: attachment halves "
      "tau1/tau2). Selectors: a physical group, point:x,y,z or plane:px,py,pz,nx,ny,nz. "
      "PETSc options for the solve take the prefix fibers_ (after --).");
  sub->add_option("mesh", options->mesh, "the mesh (.msh, tetrahedra or hexahedra)")->required();
  sub->add_option("--rule", options->rule, "FD1 or FD2")->required();
  sub->add_option("--leaflet", options->leaflets,
                  "a leaflet volume group (repeatable; default: every volume group named leaflet*, else the "
                  "whole mesh)");
  sub->add_option("--n1", options->n1, "FD1: where u = 1 (default group <leaflet>_n1 or n1)");
  sub->add_option("--n2", options->n2, "FD1: where u = 0 (default group <leaflet>_n2 or n2)");
  sub->add_option("--tau1", options->tau1, "FD2: where u = 0 (default group <leaflet>_tau1 or tau1)");
  sub->add_option("--tau2", options->tau2, "FD2: where u = 1 (default group <leaflet>_tau2 or tau2)");
  sub->add_option(
      "--attachment", options->attachment,
      "FD2 without tau groups: the attachment surface, split by the plane through the axis and the "
      "leaflet's centroid (default group <leaflet>_attachment or attachment)");
  sub->add_option("--axis", options->axis,
                  "valve axis point and direction px py pz dx dy dz (default 0 0 0 0 0 1)")
      ->expected(6)
      ->delimiter(',');
  sub->add_option("-o,--output", options->output, "output folder")->required()->check(non_empty_path);
  sub->add_flag("--overwrite", options->overwrite, "write into an existing, non-empty folder");
  sub->callback(
      [options, &action] { action = [options](const PetscArguments&) { return run_fibers(*options); }; });
}

} // namespace ibvalve::app
