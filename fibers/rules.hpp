#pragma once
// The study's fiber architectures for valve leaflets (Zhu et al. 2021; docs/reference.md, "Fiber
// architectures"), each a Laplace problem on one leaflet (a volume physical group) with
// f0 = grad u / |grad u|:
//   FD1 (body-fitted):    u = 1 at corner point n1, u = 0 at corner point n2 (the free edge's ends).
//   FD2 (circumferential): u = 0 on tau1, u = 1 on tau2, the two halves of the attachment surface,
//                          symmetric about the leaflet's centre line.
// Dirichlet sets are selectors (fibers/laplace.hpp): a physical group, "point:x,y,z" or
// "plane:...". Left empty they default to the groups "<leaflet>_n1", "<leaflet>_n2", "<leaflet>_tau1",
// "<leaflet>_tau2" or, failing those, "n1", "n2", "tau1", "tau2". For FD2 without tau groups, an
// attachment surface group ("<leaflet>_attachment" or "attachment") is split in two by the plane
// through the valve axis and the leaflet's centroid.
#include <filesystem>
#include <string>
#include <vector>

#include "fibers/laplace.hpp"

namespace ibvalve::fibers {

enum class FiberRule { FD1, FD2 };

/// "FD1" or "FD2" (case-insensitive); InputError otherwise.
FiberRule parse_fiber_rule(const std::string& text);

struct LeafletSpec {
  std::string group; ///< volume group; empty means the whole mesh
  std::string n1, n2, tau1, tau2, attachment;
  Vec3 axis_point = Vec3::Zero();
  Vec3 axis_direction = Vec3::UnitZ();
};

struct FiberField {
  std::vector<Vec3> element_directions; ///< one per mesh element; zero outside every leaflet
  std::vector<double> potential;        ///< nodal Laplace solution (each leaflet's own)
  std::vector<double> dirichlet;        ///< nodal: -1 free, else the Dirichlet value
};

FiberField compute_fibers(const fe::Mesh& mesh, FiberRule rule, const std::vector<LeafletSpec>& leaflets,
                          MPI_Comm comm, const LaplaceOptions& options = {});

/// Per-element fiber file a run reads back: a header line "ibvalve-element-fibers 1 <elements>",
/// then one line "fx fy fz" per element (17 significant digits). Written by rank 0 of `comm`.
void write_element_fibers(const std::filesystem::path& path, const std::vector<Vec3>& directions,
                          MPI_Comm comm);
/// Reads the file; InputError "file:line: ..." on a bad header, a short file, or a count other than
/// `expected_elements` (when >= 0).
std::vector<Vec3> read_element_fibers(const std::filesystem::path& path, long expected_elements = -1);

} // namespace ibvalve::fibers
