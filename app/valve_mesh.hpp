#pragma once
// The aortic-valve model's structure: a Gmsh mesh of one's own (`mesh.file`) or the idealized valve
// generated at start-up (fe/valve_mesh.hpp, the generator's `mesh.*` keys), and the physical groups the
// model reads from it (docs/own-valve.md lists them). A mesh that lacks groups is one error naming the
// file and every group it lacks.
#include <filesystem>
#include <string>
#include <vector>

#include <mpi.h>

#include "fe/mesh.hpp"
#include "fe/valve_mesh.hpp"
#include "fibers/rules.hpp"
#include "io/key_binder.hpp"
#include "materials/strain_energy.hpp"

namespace ibvalve::app {

struct ValveMeshKeys {
  std::filesystem::path file; ///< empty: generate the mesh from `geometry`
  /// The valve's geometry: the generator's parameters; with a mesh file the tube's radius and wall, the
  /// leaflets' thickness, the nadir's height and the commissures' (where the model puts its probes,
  /// pressure disks and leaflet spheres) describe that mesh, and the generator's own keys are unused.
  fe::ValveMeshParameters geometry;
};

/// mesh.file and the mesh.* keys, each defaulting to fe::ValveMeshParameters (what `ibvalve mesh
/// aortic-valve` generates); the generator's resolution and shape keys are not used with mesh.file
/// (io::KeyBuilder::unused_with).
void bind(io::KeyBinder& keys, ValveMeshKeys& k);

/// A group the model reads from the mesh and what it does with it.
struct ValveMeshGroup {
  std::string name;
  bool volume = false; ///< a volume group (elements); else any group of nodes (surface, curve, points)
  std::string use;
};

/// The groups the aortic-valve model needs in a mesh of `leaflets` leaflets whose fibers follow `rule`,
/// with the tube's surfaces `tethered` held (named by the key `tethered_key`); without `tube` (tube.model =
/// "wall") neither the tube's volume nor its surfaces.
std::vector<ValveMeshGroup> required_valve_groups(int leaflets, fibers::FiberRule rule, bool tube,
                                                  const std::vector<std::string>& tethered,
                                                  const std::string& tethered_key);

/// "" when `mesh` has every group of `required` (volume groups as volume groups); else one message naming
/// every group it lacks: "the mesh lacks 3 groups: leaflet1 (a volume group: ...), ...".
std::string missing_groups(const fe::Mesh& mesh, const std::vector<ValveMeshGroup>& required);

/// The hexahedra and nodes of the generated valve, known before it is built (for the size checks).
struct GeneratedSize {
  double elements = 0, nodes = 0;
  bool tube_dominates = false; ///< more tube elements than leaflet elements
};
GeneratedSize generated_size(const fe::ValveMeshParameters& geometry, int leaflets);

/// The leaflets' fibers by `rule` (fibers/rules.hpp), a Laplace problem on each leaflet's volume group
/// with its own groups' Dirichlet data, as one frame per element (zero outside the leaflets). Collective
/// over `comm`; InputError when the groups do not give a fiber field.
std::vector<materials::FiberFrame> leaflet_fibers(const fe::Mesh& mesh, fibers::FiberRule rule, int leaflets,
                                                  MPI_Comm comm);

/// "mesh: FILE (N hexahedra, M nodes; leaflet1 ..., tube ...)" or "mesh: generated (...)": where the
/// structure came from, for the run's log and `ibvalve check`.
std::string describe_valve_mesh(const ValveMeshKeys& keys, const fe::Mesh& mesh, int leaflets);

} // namespace ibvalve::app
