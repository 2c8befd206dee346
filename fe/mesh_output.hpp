#pragma once
// Mesh fields to HDF5 + XDMF for ParaView: one HDF5 file per output step holding the REFERENCE node
// coordinates, the connectivity and the fields (node- or cell-centred, scalars or 3-vectors, each with
// its `units` attribute and "name [units]" in the XDMF), and an XDMF time series (io/xdmf.hpp) pointing
// at them. Open <name>.xdmf in ParaView ("Xdmf3 Reader"), and use "Warp By Vector" with `displacement`
// to see the deformed body. (A run's fields/step_*.h5, app/ibfe_fields.hpp, hold the current positions
// instead: no warp there.)
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <mpi.h>

#include "fe/mass.hpp"
#include "fe/solid.hpp"
#include "io/xdmf.hpp"

namespace ibvalve::fe {

struct MeshField {
  std::string name;
  io::Center center = io::Center::cell;
  int components = 1; ///< 1 or 3
  std::vector<double> values;
  std::string units = ""; ///< CGS, "1" for a pure number
};

/// Writes the mesh and `fields` to `h5_path` (collective; rank 0 writes the replicated data) and
/// returns the XDMF grid describing them, with data paths relative to `xdmf_directory`.
io::XdmfGrid write_mesh_fields(MPI_Comm comm, const Mesh& mesh, const std::filesystem::path& h5_path,
                               const std::filesystem::path& xdmf_directory, const std::string& grid_name,
                               const std::vector<MeshField>& fields);

/// A time series of mesh fields: <directory>/<name>_<step>.h5 and <directory>/<name>.xdmf.
class MeshOutput {
 public:
  MeshOutput(MPI_Comm comm, const Mesh& mesh, std::filesystem::path directory, std::string name = "mesh");
  void write(double time, const std::vector<MeshField>& fields);
  const std::filesystem::path& xdmf_path() const { return xdmf_path_; }

 private:
  MPI_Comm comm_;
  const Mesh& mesh_;
  std::filesystem::path directory_;
  std::string name_;
  std::filesystem::path xdmf_path_;
  io::XdmfTimeSeries series_;
  int step_ = 0;
};

/// The solid's fields at displacement u (docs/reference.md, "Hemodynamic metrics"): nodal
/// displacement; per element J, fiber strain f0.(E f0), fiber stress f.(sigma f) (dyn/cm^2), current fiber
/// direction f and reference f0. With a projection (built on solid.quadrature()), also the nodal L2
/// projections of J, fiber strain and fiber stress ("J_nodal", "fiber_strain_nodal", "fiber_stress_nodal")
/// for smooth pictures.
std::vector<MeshField> solid_fields(const SolidModel& solid, std::span<const double> u,
                                    const L2Projection* projection = nullptr);

} // namespace ibvalve::fe
