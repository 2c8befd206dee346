#include "app/ibfe_fields.hpp"

#include <array>
#include <cstdio>
#include <sstream>
#include <vector>

#include "fe/element.hpp"
#include "fluid/composite_output.hpp"
#include "fluid/output.hpp"
#include "io/collective.hpp"
#include "io/petsc_check.hpp"

namespace ibvalve::app {

void create_fields_directory(MPI_Comm comm, const std::filesystem::path& directory)
{
  io::create_directories_on_root(comm, directory / "fields");
}

std::string fields_file_name(long step)
{
  char name[64];
  std::snprintf(name, sizeof name, "fields/step_%06ld.h5", step);
  return name;
}

io::XdmfGrid write_structure_fields(io::Hdf5File& h5, const fe::Mesh& mesh, const ib::IbfeIntegrator& ibfe,
                                    const std::string& file)
{
  // The mesh is replicated on every rank: current coordinates, nodal and element fields.
  const std::size_t nodes = mesh.num_nodes(), elements = mesh.num_elements();
  const std::size_t per_element = static_cast<std::size_t>(mesh.nodes_per_element());
  std::vector<std::int64_t> connectivity(mesh.connectivity().begin(), mesh.connectivity().end());
  std::vector<double> coordinates(3 * nodes);
  const auto x = ibfe.positions();
  for (std::size_t i = 0; i < nodes; ++i)
    for (int d = 0; d < 3; ++d) coordinates[3 * i + d] = x[i][d];
  const fe::ElementFields ef = ibfe.solid().element_fields(ibfe.displacement());
  const std::vector<hsize_t> node_vector{nodes, 3}, cell_scalar{elements}, cell_nodes{elements, per_element};
  h5.write_root("mesh/connectivity", connectivity, cell_nodes);
  h5.write_root("mesh/coordinates", coordinates, node_vector);
  h5.write_root("mesh/displacement", ibfe.displacement(), node_vector);
  h5.write_root("mesh/velocity", ibfe.velocity(), node_vector);
  h5.write_root("mesh/J", ef.J, cell_scalar);
  h5.write_root("mesh/fiber_strain", ef.fiber_strain, cell_scalar);
  h5.write_root("mesh/fiber_stress", ef.fiber_stress, cell_scalar);
  auto structure = io::XdmfGrid::mesh("structure", fe::xdmf_topology(mesh.shape()), elements, per_element,
                                      file + ":/mesh/connectivity", nodes, file + ":/mesh/coordinates");
  structure.add_field("displacement", io::Center::node, {nodes, 3}, file + ":/mesh/displacement")
      .add_field("velocity", io::Center::node, {nodes, 3}, file + ":/mesh/velocity")
      .add_field("J", io::Center::cell, {elements}, file + ":/mesh/J")
      .add_field("fiber_strain", io::Center::cell, {elements}, file + ":/mesh/fiber_strain")
      .add_field("fiber_stress", io::Center::cell, {elements}, file + ":/mesh/fiber_stress");
  return structure;
}

void write_ibfe_fields(MPI_Comm comm, const std::filesystem::path& directory, io::XdmfTimeSeries& series,
                       const fe::Mesh& mesh, const fluid::NavierStokes& fluid, const ib::IbfeIntegrator& ibfe,
                       long step)
{
  const std::string file = fields_file_name(step);
  io::Hdf5File h5(comm, directory / file, io::Hdf5File::Mode::create);
  // The grid: cell-centred velocity, vorticity and pressure (fluid/output.hpp).
  io::XdmfGrid grid = fluid::write_fields(h5, fluid, "fluid", file);
  io::XdmfGrid structure = write_structure_fields(h5, mesh, ibfe, file);
  series.add_step(ibfe.time(), {grid, structure});
}

void write_ibfe_fields(MPI_Comm comm, const std::filesystem::path& directory, io::XdmfTimeSeries& series,
                       const fe::Mesh& mesh, const fluid::NestedNavierStokes& fluid,
                       const ib::IbfeIntegrator& ibfe, long step)
{
  const std::string file = fields_file_name(step);
  io::Hdf5File h5(comm, directory / file, io::Hdf5File::Mode::create);
  // The cell velocity's vectors are owned, so they are freed also when a write throws (a full disk must
  // not leak them); `components` borrows their handles for the calls that take an array.
  std::array<petsc::OwnedVec, 3> owned;
  std::array<Vec, 3> components{};
  for (std::size_t d = 0; d < 3; ++d) {
    owned[d] = fluid.operators().create_cell_vector();
    components[d] = owned[d];
  }
  fluid.cell_velocity(components);
  std::vector<io::XdmfGrid> grids =
      fluid::write_composite_fields(h5, fluid.operators().cells(), {{"pressure", fluid.pressure()}}, "fluid",
                                    file, "fluid_", {{"velocity", components}});
  grids.push_back(write_structure_fields(h5, mesh, ibfe, file));
  series.add_step(ibfe.time(), grids);
}

std::vector<std::string> ibfe_summary_lines(const ib::IbfeIntegrator& ibfe, double initial_volume,
                                            const std::filesystem::path& directory, std::size_t outputs,
                                            const std::string& after_parts)
{
  const ib::IbfeTimings& t = ibfe.timings();
  std::ostringstream timing;
  timing.precision(3);
  timing << "per coupled step: " << t.total / t.steps << " s (fluid " << t.fluid / t.steps
         << ", interpolation " << t.interpolation / t.steps << ", projection " << t.projection / t.steps
         << ", force " << t.force / t.steps << ", spreading " << t.spreading / t.steps << ")" << after_parts;
  return {timing.str(),
          "structure volume change " + std::to_string(100.0 * (ibfe.volume() / initial_volume - 1.0)) + " %",
          "fields: " + (directory / "fields.xdmf").string() + " (" + std::to_string(outputs) +
              " outputs), time series: " + (directory / "timeseries.csv").string()};
}

} // namespace ibvalve::app
