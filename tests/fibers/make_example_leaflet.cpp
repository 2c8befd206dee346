// Writes examples/fibers/leaflet.msh: one flat leaflet-like annular sector (a third of a closed
// valve seen along its axis): r in [0.05, 1.3] cm, theta in [0, 120] degrees, thickness 0.04 cm,
// trilinear hexahedra. Groups: "leaflet" (volume); "leaflet_attachment" (the outer arc r = 1.3, where
// a leaflet meets the aorta); "leaflet_free_edge" (the two radial faces, along the coaptation lines);
// "leaflet_n1", "leaflet_n2" (the free edge's ends at the commissures, theta = 0 and 120 degrees on the
// outer arc, mid-thickness). Usage: make_example_leaflet OUT.msh
#include <cmath>
#include <iostream>
#include <numbers>

#include <mpi.h>

#include "fe/gmsh_io.hpp"
#include "fibers/laplace.hpp"

int main(int argc, char** argv)
{
  using namespace ibvalve;
  if (argc != 2) {
    std::cerr << "usage: make_example_leaflet OUT.msh\n";
    return 2;
  }
  MPI_Init(&argc, &argv);
  const double radius = 1.3, angle = 2 * std::numbers::pi / 3, thickness = 0.04;
  const fe::Mesh sector =
      fe::annular_sector_mesh(fe::CellShape::hexahedron, 0.05, radius, angle, thickness, {8, 24, 1});
  fe::Mesh mesh(sector.shape(), sector.nodes(), sector.connectivity());
  mesh.add_volume_group("leaflet", sector.group("body").elements);
  fe::PhysicalGroup attachment = sector.group("outer");
  attachment.name = "leaflet_attachment";
  mesh.add_group(attachment);
  fe::PhysicalGroup free_edge = sector.group("theta0");
  free_edge.name = "leaflet_free_edge";
  const auto& other = sector.group("theta1").cells;
  free_edge.cells.insert(free_edge.cells.end(), other.begin(), other.end());
  mesh.add_group(free_edge);
  mesh.add_point_group("leaflet_n1", {fibers::nearest_node(mesh, fe::Vec3(radius, 0, 0))});
  mesh.add_point_group("leaflet_n2", {fibers::nearest_node(mesh, fe::Vec3(radius * std::cos(angle),
                                                                          radius * std::sin(angle), 0))});
  fe::write_msh(mesh, argv[1]);
  std::cout << "wrote " << argv[1] << ": " << mesh.num_elements() << " hexahedra, " << mesh.num_nodes()
            << " nodes\n";
  MPI_Finalize();
  return 0;
}
