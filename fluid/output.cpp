#include "fluid/output.hpp"

#include <vector>

#include "fluid/queries.hpp"

namespace ibvalve::fluid {

io::XdmfGrid write_fields(io::Hdf5File& file, const NavierStokes& fluid, const std::string& group,
                          const std::string& file_reference, const std::string& grid_name)
{
  const StaggeredGrid& grid = fluid.grid();
  const CellFields cells = cell_fields(fluid);
  const std::array<std::size_t, 3> n{static_cast<std::size_t>(grid.cells(0)),
                                     static_cast<std::size_t>(grid.cells(1)),
                                     static_cast<std::size_t>(grid.cells(2))};
  const std::vector<hsize_t> scalar_dims{n[2], n[1], n[0]}, vector_dims{n[2], n[1], n[0], 3};
  const std::vector<hsize_t> offset{static_cast<hsize_t>(cells.begin[2]),
                                    static_cast<hsize_t>(cells.begin[1]),
                                    static_cast<hsize_t>(cells.begin[0]), 0};
  const std::vector<hsize_t> count{static_cast<hsize_t>(cells.count[2]), static_cast<hsize_t>(cells.count[1]),
                                   static_cast<hsize_t>(cells.count[0]), 3};
  file.write_block(group + "/velocity", cells.velocity, vector_dims, offset, count);
  file.write_block(group + "/vorticity", cells.vorticity, vector_dims, offset, count);
  file.write_block(group + "/pressure", cells.pressure, scalar_dims, std::span(offset).first(3),
                   std::span(count).first(3));
  const std::array<std::pair<const char*, const char*>, 3> units{
      {{"velocity", "cm/s"}, {"vorticity", "1/s"}, {"pressure", "dyn/cm^2"}}};
  for (const auto& [name, unit] : units) file.write_string_attribute(group + "/" + name, "units", unit);
  const BoxGeometry& box = grid.box();
  auto xdmf = io::XdmfGrid::regular(grid_name, n, {box.lower[0], box.lower[1], box.lower[2]},
                                    {grid.h(0), grid.h(1), grid.h(2)});
  const std::string prefix = file_reference + ":/" + group + "/";
  xdmf.add_field("velocity", io::Center::cell, {n[2], n[1], n[0], 3}, prefix + "velocity", "cm/s")
      .add_field("vorticity", io::Center::cell, {n[2], n[1], n[0], 3}, prefix + "vorticity", "1/s")
      .add_field("pressure", io::Center::cell, {n[2], n[1], n[0]}, prefix + "pressure", "dyn/cm^2");
  return xdmf;
}

} // namespace ibvalve::fluid
