#pragma once
// Field snapshots of an IB/FE run (the ibfe and aortic-valve models): one HDF5 file per snapshot,
// <run>/fields/step_<n>.h5, with the fluid's cell-centred velocity, vorticity and pressure (each rank
// writes its block) and the structure's current mesh with its displacement, velocity, J and fiber strain
// and stress, plus one entry in <run>/fields.xdmf so ParaView ("Xdmf3 Reader") shows both together.
#include <filesystem>

#include <mpi.h>

#include "fe/mesh.hpp"
#include "fluid/grid.hpp"
#include "fluid/navier_stokes.hpp"
#include "ib/ibfe.hpp"
#include "io/xdmf.hpp"

namespace ibvalve::app {

/// Creates <directory>/fields (collective).
void create_fields_directory(MPI_Comm comm, const std::filesystem::path& directory);

/// Writes the snapshot of step `step` and adds it to `series` (collective).
void write_ibfe_fields(MPI_Comm comm, const std::filesystem::path& directory, io::XdmfTimeSeries& series,
                       const fluid::BoxGeometry& box, const fe::Mesh& mesh, const fluid::NavierStokes& fluid,
                       const ib::IbfeIntegrator& ibfe, long step);

} // namespace ibvalve::app
