#include "fe/mesh_output.hpp"

#include <cstdio>

#include <fmt/format.h>

#include "io/hdf5.hpp"

namespace ibvalve::fe {

io::XdmfGrid write_mesh_fields(MPI_Comm comm, const Mesh& mesh, const std::filesystem::path& h5_path,
                               const std::filesystem::path& xdmf_directory, const std::string& grid_name,
                               const std::vector<MeshField>& fields)
{
  io::Hdf5File file(comm, h5_path, io::Hdf5File::Mode::create);
  std::vector<double> coordinates;
  coordinates.reserve(3 * mesh.num_nodes());
  for (const Vec3& x : mesh.nodes()) coordinates.insert(coordinates.end(), {x[0], x[1], x[2]});
  const std::vector<std::int64_t> connectivity(mesh.connectivity().begin(), mesh.connectivity().end());
  const std::array<hsize_t, 2> node_dims{mesh.num_nodes(), 3};
  const std::array<hsize_t, 2> cell_dims{mesh.num_elements(), static_cast<hsize_t>(mesh.nodes_per_element())};
  file.write_root("coordinates", coordinates, node_dims);
  file.write_string_attribute("coordinates", "units", "cm");
  file.write_string_attribute("coordinates", "description",
                              "reference positions X (cm): Warp By Vector with displacement shows the "
                              "deformed body");
  file.write_root("connectivity", connectivity, cell_dims);

  const std::string relative = std::filesystem::relative(h5_path, xdmf_directory).generic_string();
  io::XdmfGrid grid = io::XdmfGrid::mesh(grid_name, xdmf_topology(mesh.shape()), mesh.num_elements(),
                                         mesh.nodes_per_element(), relative + ":/connectivity",
                                         mesh.num_nodes(), relative + ":/coordinates");
  grid.add_information("geometry", "reference positions X (cm): Warp By Vector with displacement shows the "
                                   "deformed body");
  for (const MeshField& field : fields) {
    const std::size_t count = field.center == io::Center::node ? mesh.num_nodes() : mesh.num_elements();
    std::vector<std::size_t> dims{count};
    if (field.components > 1) dims.push_back(static_cast<std::size_t>(field.components));
    if (field.values.size() != count * field.components)
      throw std::logic_error("write_mesh_fields: field '" + field.name + "' has the wrong size");
    const std::vector<hsize_t> h5_dims(dims.begin(), dims.end());
    file.write_root(field.name, field.values, h5_dims);
    if (!field.units.empty()) file.write_string_attribute(field.name, "units", field.units);
    grid.add_field(field.name, field.center, dims, relative + ":/" + field.name, field.units);
  }
  file.close(); // a failure to write it (a full disk) is a RunError on every rank
  return grid;
}

MeshOutput::MeshOutput(MPI_Comm comm, const Mesh& mesh, std::filesystem::path directory, std::string name)
    : comm_(comm), mesh_(mesh), directory_(std::move(directory)), name_(std::move(name)),
      xdmf_path_(directory_ / (name_ + ".xdmf")), series_(comm, xdmf_path_, name_)
{
}

void MeshOutput::write(double time, const std::vector<MeshField>& fields)
{
  const std::filesystem::path h5 = directory_ / fmt::format("{}_{:06}.h5", name_, step_++);
  series_.add_step(time, {write_mesh_fields(comm_, mesh_, h5, directory_, name_, fields)});
}

std::vector<MeshField> solid_fields(const SolidModel& solid, std::span<const double> u,
                                    const L2Projection* projection)
{
  const Mesh& mesh = solid.mesh();
  const ElementFields element = solid.element_fields(u);
  std::vector<MeshField> fields;
  fields.push_back({"displacement", io::Center::node, 3, std::vector<double>(u.begin(), u.end()), "cm"});
  fields.push_back({"J", io::Center::cell, 1, element.J, "1"});
  fields.push_back({"fiber_strain", io::Center::cell, 1, element.fiber_strain, "1"});
  fields.push_back({"fiber_stress", io::Center::cell, 1, element.fiber_stress, "dyn/cm^2"});
  MeshField current{"fiber_direction", io::Center::cell, 3, {}, "1"},
      reference{"fiber_reference", io::Center::cell, 3, {}, "1"};
  for (std::size_t e = 0; e < mesh.num_elements(); ++e) {
    const Vec3& f = element.fiber_direction[e];
    current.values.insert(current.values.end(), {f[0], f[1], f[2]});
    const Vec3& f0 = solid.fibers(e, 0).f0;
    reference.values.insert(reference.values.end(), {f0[0], f0[1], f0[2]});
  }
  fields.push_back(std::move(current));
  fields.push_back(std::move(reference));
  if (projection) {
    const PointFields points = solid.point_fields(u);
    fields.push_back({"J_nodal", io::Center::node, 1, projection->project(points.J, 1), "1"});
    fields.push_back(
        {"fiber_strain_nodal", io::Center::node, 1, projection->project(points.fiber_strain, 1), "1"});
    fields.push_back(
        {"fiber_stress_nodal", io::Center::node, 1, projection->project(points.fiber_stress, 1), "dyn/cm^2"});
  }
  return fields;
}

} // namespace ibvalve::fe
