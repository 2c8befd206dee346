// Mesh fields go to HDF5 + XDMF: the datasets read back equal what was written (coordinates,
// connectivity, nodal displacement, per-element J and fiber strain), and the XDMF names the topology
// and every field with its centring, on 1 and 2 ranks.
#include <cmath>
#include <filesystem>
#include <memory>

#include <gtest/gtest.h>

#include "fe/mesh_output.hpp"
#include "io/files.hpp"
#include "io/hdf5.hpp"
#include "tests/fe/neo_hookean_fixture.hpp"

using namespace ibvalve;
using namespace ibvalve::fe;

TEST(MeshOutput, SolidFieldsRoundTripThroughHdf5AndXdmf)
{
  const Mesh mesh = box_mesh(CellShape::tetrahedron, Vec3(0, 0, 0), Vec3(1, 1, 1), {2, 2, 2});
  SolidModel solid(mesh,
                   {BodyPart{"body",
                             mesh.group("body").elements,
                             {std::make_shared<fixtures::NeoHookeanFixture>(1e4, 4e4)}}},
                   2, PETSC_COMM_WORLD);
  materials::FiberFrame frame;
  frame.f0 = Vec3::UnitX();
  solid.set_fibers(std::vector<materials::FiberFrame>(mesh.num_elements(), frame));
  // Uniaxial stretch 1.1 along the fibers: J = 1.1, fiber strain (1.1^2 - 1)/2 = 0.105.
  std::vector<double> u(3 * mesh.num_nodes(), 0.0);
  for (std::size_t n = 0; n < mesh.num_nodes(); ++n) u[3 * n] = 0.1 * mesh.nodes()[n][0];
  const std::filesystem::path directory = "mesh_output_test";
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0) std::filesystem::create_directories(directory);
  MPI_Barrier(PETSC_COMM_WORLD);
  {
    MeshOutput output(PETSC_COMM_WORLD, mesh, directory, "solid");
    const L2Projection projection(mesh, solid.quadrature(), MassKind::consistent, PETSC_COMM_WORLD);
    output.write(0.0, solid_fields(solid, std::vector<double>(u.size(), 0.0)));
    output.write(0.5, solid_fields(solid, u, &projection));
  }
  MPI_Barrier(PETSC_COMM_WORLD);
  io::Hdf5File file(PETSC_COMM_WORLD, directory / "solid_000001.h5", io::Hdf5File::Mode::read);
  const std::vector<double> J = file.read("J"), strain = file.read("fiber_strain"),
                            displacement = file.read("displacement");
  ASSERT_EQ(J.size(), mesh.num_elements());
  for (std::size_t e = 0; e < mesh.num_elements(); ++e) {
    EXPECT_NEAR(J[e], 1.1, 1e-14);
    EXPECT_NEAR(strain[e], 0.105, 1e-14);
  }
  EXPECT_EQ(displacement, u);
  // Homogeneous fields project to the same constants at the nodes.
  const std::vector<double> J_nodal = file.read("J_nodal"), strain_nodal = file.read("fiber_strain_nodal"),
                            stress_nodal = file.read("fiber_stress_nodal"),
                            stress = file.read("fiber_stress");
  ASSERT_EQ(J_nodal.size(), mesh.num_nodes());
  for (std::size_t n = 0; n < mesh.num_nodes(); ++n) {
    EXPECT_NEAR(J_nodal[n], 1.1, 1e-10);
    EXPECT_NEAR(strain_nodal[n], 0.105, 1e-10);
    EXPECT_NEAR(stress_nodal[n], stress[0], 1e-10 * std::abs(stress[0]));
  }
  // f . sigma f of the neo-Hookean fixture for F = diag(1.1, 1, 1): (mu (1.21 - 1) + lambda ln 1.1) / 1.1.
  EXPECT_NEAR(stress[0], (1e4 * 0.21 + 4e4 * std::log(1.1)) / 1.1, 1e-9);
  const std::vector<std::int64_t> connectivity = file.read_integers("connectivity");
  EXPECT_TRUE(std::equal(connectivity.begin(), connectivity.end(), mesh.connectivity().begin()));
  const std::string xdmf = io::read_text_file(directory / "solid.xdmf");
  EXPECT_NE(xdmf.find("TopologyType=\"Tetrahedron\""), std::string::npos);
  // The names ParaView lists carry the units (none for pure numbers); so does each dataset.
  for (const char* name : {"displacement [cm]", "J", "fiber_strain", "fiber_stress [dyn/cm^2]",
                           "fiber_direction", "fiber_reference"})
    EXPECT_NE(xdmf.find(std::string("Name=\"") + name + "\""), std::string::npos) << name;
  EXPECT_EQ(file.read_string_attribute("displacement", "units"), "cm");
  EXPECT_EQ(file.read_string_attribute("fiber_stress", "units"), "dyn/cm^2");
  EXPECT_EQ(file.read_string_attribute("J", "units"), "1");
  EXPECT_EQ(file.read_string_attribute("coordinates", "units"), "cm");
  EXPECT_NE(xdmf.find("<Information Name=\"geometry\" Value=\"reference positions"), std::string::npos);
  EXPECT_NE(xdmf.find("solid_000001.h5:/J"), std::string::npos);
  EXPECT_NE(xdmf.find("<Time Value=\"0.5\"/>"), std::string::npos);
}
