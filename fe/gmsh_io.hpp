#pragma once
// Reading and writing Gmsh .msh files through the gmsh API (libgmsh), with named physical groups.
#include <filesystem>

#include "fe/mesh.hpp"

namespace ibvalve::fe {

/// Keeps the gmsh library initialised while any session object lives (reference counted), so that
/// several users in one process (reader, writer, mesh generator) share one gmsh::initialize /
/// gmsh::finalize pair.
class GmshSession {
 public:
  GmshSession();
  ~GmshSession();
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;
};

/// Reads a mesh of first-order tetrahedra or hexahedra (one kind) with its physical groups. Nodes
/// that no 3-D element uses are dropped. Volume groups become element sets; surface, curve and point
/// groups become cell sets with their nodes. InputError (naming the file) for a missing or unreadable
/// file, a mesh without 3-D elements, mixed or higher-order cells, or unnamed groups (which are
/// named "<dim>d_<tag>").
Mesh read_msh(const std::filesystem::path& path);

/// Writes `mesh` as MSH 4.1 with one discrete entity per distinct set of volume groups an element
/// belongs to, one entity per lower-dimensional group, and every group named. Call on one rank.
void write_msh(const Mesh& mesh, const std::filesystem::path& path);

} // namespace ibvalve::fe
