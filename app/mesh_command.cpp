// `ibvalve mesh aortic-valve [options] -o valve.msh`: the idealized tri-leaflet valve in its tube
// (fe/valve_mesh.hpp), written as a Gmsh file with physical groups, plus an XDMF/HDF5 copy ParaView opens.
#include <array>
#include <filesystem>
#include <fmt/format.h>
#include <stdexcept>
#include <utility>

#include <mpi.h>

#include "app/commands.hpp"
#include "app/resource_estimate.hpp"
#include "base/errors.hpp"
#include "base/logger.hpp"
#include "fe/gmsh_io.hpp"
#include "fe/valve_mesh.hpp"
#include "io/collective.hpp"
#include "io/files.hpp"

namespace ibvalve::app {

namespace {

/// The most hexahedra the command generates: some gigabytes to build and write, where a valve ibvalve
/// runs has tens of thousands.
constexpr double max_generated_elements = 1e7;

/// InputError for element counts beyond what a case file may ask (app/resource_estimate.hpp), each or
/// all together, before anything is allocated.
void check_counts(const fe::ValveMeshParameters& p)
{
  const std::array<std::pair<int, const char*>, 6> counts{{{p.leaflet_across, "--leaflet-across"},
                                                           {p.leaflet_radial, "--leaflet-radial"},
                                                           {p.leaflet_through, "--leaflet-through"},
                                                           {p.tube_around, "--tube-around"},
                                                           {p.tube_along, "--tube-along"},
                                                           {p.tube_through, "--tube-through"}}};
  for (const auto& [count, option] : counts)
    if (count > max_mesh_cells)
      throw InputError(
          fmt::format("command line: {} {}: at most {} elements", option, count, max_mesh_cells));
  const double elements =
      3.0 * p.leaflet_across * p.leaflet_radial * p.leaflet_through +
      (p.include_tube ? static_cast<double>(p.tube_around) * p.tube_along * p.tube_through : 0.0);
  if (elements > max_generated_elements)
    throw InputError(
        fmt::format("command line: ibvalve mesh aortic-valve: {:.3g} hexahedra, more than the {:.0e} "
                    "it generates (fewer elements along or around the tube?)",
                    elements, max_generated_elements));
}

int write_valve_mesh(const fe::ValveMeshParameters& parameters, const std::filesystem::path& output)
{
  check_counts(parameters);
  try {
    fe::check(parameters);
  } catch (const std::invalid_argument& error) {
    throw InputError(std::string("command line: ibvalve mesh aortic-valve: ") + error.what());
  }
  if (output.extension() != ".msh") throw InputError(output.string() + ": the output must be a .msh file");
  const fe::Mesh mesh = fe::aortic_valve_mesh(parameters);
  // Rank 0 writes; a folder that cannot be made (a path below a regular file, /proc) is bad input on
  // every rank, so none waits for rank 0.
  io::on_root(MPI_COMM_WORLD, [&] {
    if (output.has_parent_path()) io::create_output_folder(output.parent_path());
    fe::write_msh(mesh, output);
  });
  auto& log = base::Logger::global();
  log.info(fmt::format("wrote {}: {} hexahedra, {} nodes", output.string(), mesh.num_elements(),
                       mesh.num_nodes()));
  std::string groups;
  for (const auto& g : mesh.groups()) groups += (groups.empty() ? "" : ", ") + g.name;
  log.info("physical groups: " + groups);
  return 0;
}

} // namespace

void add_mesh_command(CLI::App& app, CommandAction& action)
{
  CLI::App* mesh = app.add_subcommand("mesh", "Generate a structure mesh (Gmsh .msh with physical groups)");
  mesh->require_subcommand(1);
  auto parameters = std::make_shared<fe::ValveMeshParameters>();
  auto output = std::make_shared<std::filesystem::path>("valve.msh");
  CLI::App* valve =
      mesh->add_subcommand("aortic-valve", "idealized tri-leaflet aortic valve in a straight tube "
                                           "(lengths in cm; docs/fe.md)");
  auto& p = *parameters;
  valve->add_option("-o,--output", *output, "output .msh file")->capture_default_str()->check(non_empty_path);
  valve->add_option("--tube-radius", p.tube_radius, "inner radius of the tube")->capture_default_str();
  valve->add_option("--tube-wall", p.tube_wall, "tube wall thickness")->capture_default_str();
  valve->add_option("--tube-length", p.tube_length, "tube length (inlet at z = 0)")->capture_default_str();
  valve->add_option("--leaflet-thickness", p.leaflet_thickness, "leaflet thickness")->capture_default_str();
  valve->add_option("--valve-base", p.valve_base, "z of the attachment's lowest point")
      ->capture_default_str();
  valve->add_option("--commissure-height", p.commissure_height, "commissure height above the base")
      ->capture_default_str();
  valve->add_option("--commissure-strip", p.commissure_strip, "attachment strip up the wall at commissures")
      ->capture_default_str();
  valve->add_option("--sag", p.sag, "belly depth toward the ventricle")->capture_default_str();
  valve
      ->add_option("--free-edge-drop", p.free_edge_drop,
                   "how far the free edge descends from the commissures to the centre (slack for opening)")
      ->capture_default_str();
  valve->add_option("--free-edge-gap", p.free_edge_gap, "gap between closed neighbouring leaflets")
      ->capture_default_str();
  valve->add_option("--leaflet-across", p.leaflet_across, "elements from commissure to commissure (even)")
      ->capture_default_str();
  valve->add_option("--leaflet-radial", p.leaflet_radial, "elements from attachment to free edge")
      ->capture_default_str();
  valve->add_option("--leaflet-through", p.leaflet_through, "elements through the leaflet")
      ->capture_default_str();
  valve->add_option("--tube-around", p.tube_around, "tube elements around")->capture_default_str();
  valve->add_option("--tube-along", p.tube_along, "tube elements along")->capture_default_str();
  valve->add_option("--tube-through", p.tube_through, "tube elements through the wall")
      ->capture_default_str();
  valve->add_flag("!--no-tube", p.include_tube, "leaflets only");
  valve->callback([parameters, output, &action] {
    action = [parameters, output](const PetscArguments&) { return write_valve_mesh(*parameters, *output); };
  });
}

} // namespace ibvalve::app
