#include "app/ibfe_fields.hpp"

#include <cstdio>
#include <string>
#include <vector>

#include "fe/element.hpp"
#include "fluid/queries.hpp"
#include "io/hdf5.hpp"

namespace ibvalve::app {

void create_fields_directory(MPI_Comm comm, const std::filesystem::path& directory)
{
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  if (rank == 0) std::filesystem::create_directories(directory / "fields");
  MPI_Barrier(comm);
}

void write_ibfe_fields(MPI_Comm comm, const std::filesystem::path& directory, io::XdmfTimeSeries& series,
                       const fluid::BoxGeometry& box, const fe::Mesh& mesh, const fluid::NavierStokes& fluid,
                       const ib::IbfeIntegrator& ibfe, long step)
{
  char name[64];
  std::snprintf(name, sizeof name, "fields/step_%06ld.h5", step);
  const std::string file = name;
  io::Hdf5File h5(comm, directory / file, io::Hdf5File::Mode::create);
  // The grid: cell-centred velocity, vorticity (3 each) and pressure, each rank its block.
  const fluid::CellFields cells = fluid::cell_fields(fluid);
  const std::array<std::size_t, 3> n{static_cast<std::size_t>(box.cells[0]),
                                     static_cast<std::size_t>(box.cells[1]),
                                     static_cast<std::size_t>(box.cells[2])};
  const std::vector<hsize_t> scalar_dims{n[2], n[1], n[0]}, vector_dims{n[2], n[1], n[0], 3};
  const std::vector<hsize_t> offset{static_cast<hsize_t>(cells.begin[2]),
                                    static_cast<hsize_t>(cells.begin[1]),
                                    static_cast<hsize_t>(cells.begin[0]), 0};
  const std::vector<hsize_t> count{static_cast<hsize_t>(cells.count[2]), static_cast<hsize_t>(cells.count[1]),
                                   static_cast<hsize_t>(cells.count[0]), 3};
  h5.write_block("fluid/velocity", cells.velocity, vector_dims, offset, count);
  h5.write_block("fluid/vorticity", cells.vorticity, vector_dims, offset, count);
  h5.write_block("fluid/pressure", cells.pressure, scalar_dims, std::span(offset).first(3),
                 std::span(count).first(3));
  // The mesh (replicated): current coordinates, nodal and element fields.
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

  auto grid = io::XdmfGrid::regular("fluid", n, {box.lower[0], box.lower[1], box.lower[2]},
                                    {fluid.grid().h(0), fluid.grid().h(1), fluid.grid().h(2)});
  grid.add_field("velocity", io::Center::cell, {n[2], n[1], n[0], 3}, file + ":/fluid/velocity")
      .add_field("vorticity", io::Center::cell, {n[2], n[1], n[0], 3}, file + ":/fluid/vorticity")
      .add_field("pressure", io::Center::cell, {n[2], n[1], n[0]}, file + ":/fluid/pressure");
  auto structure = io::XdmfGrid::mesh("structure", fe::xdmf_topology(mesh.shape()), elements, per_element,
                                      file + ":/mesh/connectivity", nodes, file + ":/mesh/coordinates");
  structure.add_field("displacement", io::Center::node, {nodes, 3}, file + ":/mesh/displacement")
      .add_field("velocity", io::Center::node, {nodes, 3}, file + ":/mesh/velocity")
      .add_field("J", io::Center::cell, {elements}, file + ":/mesh/J")
      .add_field("fiber_strain", io::Center::cell, {elements}, file + ":/mesh/fiber_strain")
      .add_field("fiber_stress", io::Center::cell, {elements}, file + ":/mesh/fiber_stress");
  series.add_step(ibfe.time(), {grid, structure});
}

} // namespace ibvalve::app
