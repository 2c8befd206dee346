#pragma once
// Fluid fields to HDF5 (io/hdf5.hpp) with their XDMF description (io/xdmf.hpp): the cell-centred
// velocity (average of the two faces), vorticity (average of the four edges around the cell) and
// pressure, each rank writing its block of the global C-order arrays [Nz][Ny][Nx](, 3). Each dataset
// has a `units` attribute (cm/s, 1/s, dyn/cm^2) and the XDMF names carry them ("velocity [cm/s]").
#include <string>

#include "fluid/navier_stokes.hpp"
#include "io/hdf5.hpp"
#include "io/xdmf.hpp"

namespace ibvalve::fluid {

/// Writes `group`/velocity, `group`/vorticity and `group`/pressure into `file` (collective) and returns
/// the XDMF grid that describes them; `file_reference` is the HDF5 file's path as the XDMF file sees it.
io::XdmfGrid write_fields(io::Hdf5File& file, const NavierStokes& fluid, const std::string& group,
                          const std::string& file_reference, const std::string& grid_name = "fluid");

} // namespace ibvalve::fluid
