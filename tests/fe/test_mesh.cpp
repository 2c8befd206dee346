// Generated meshes have the volume and groups they claim; a .msh written and read back through the
// gmsh API keeps nodes, elements and every named physical group.
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <numbers>

#include <gmsh.h>
#include <gtest/gtest.h>
#include <mpi.h>

#include "base/errors.hpp"
#include "fe/gmsh_io.hpp"
#include "fe/loads.hpp"
#include "fe/mesh.hpp"

using namespace ibvalve::fe;

class Meshes : public ::testing::TestWithParam<CellShape> {};

TEST_P(Meshes, BoxHasItsVolumeFacesAndCorners)
{
  const Mesh mesh = box_mesh(GetParam(), Vec3(0, 0, 0), Vec3(2, 1, 0.5), {4, 3, 2});
  EXPECT_NEAR(mesh.volume(), 1.0, 1e-13);
  EXPECT_EQ(mesh.num_nodes(), 5u * 4 * 3);
  EXPECT_EQ(mesh.num_elements(), (GetParam() == CellShape::hexahedron ? 1u : 6u) * 4 * 3 * 2);
  EXPECT_NEAR(surface_area(mesh, "xmin"), 0.5, 1e-14);
  EXPECT_NEAR(surface_area(mesh, "zmax"), 2.0, 1e-14);
  EXPECT_EQ(mesh.group("xmax").nodes.size(), 4u * 3);
  EXPECT_EQ(mesh.group("corner_hi").nodes.size(), 1u);
  EXPECT_NEAR((mesh.nodes()[mesh.group("corner_hi").nodes[0]] - Vec3(2, 1, 0.5)).norm(), 0.0, 1e-15);
  EXPECT_THROW(mesh.group("no such group"), ibvalve::InputError);
}

TEST_P(Meshes, AnnularSectorVolumeConvergesToTheExactOne)
{
  // Straight-sided cells under-estimate the curved sector by O(h^2): check the error falls 4x.
  const double exact = 0.5 * (std::pow(1.2, 2) - 1.0) * (std::numbers::pi / 2) * 0.3;
  double previous = 0;
  for (int n : {4, 8, 16}) {
    const Mesh mesh = annular_sector_mesh(GetParam(), 1.0, 1.2, std::numbers::pi / 2, 0.3, {1, n, 1});
    const double error = std::abs(mesh.volume() - exact);
    if (previous > 0) {
      EXPECT_NEAR(previous / error, 4.0, 0.1);
    }
    previous = error;
  }
  const Mesh mesh = annular_sector_mesh(GetParam(), 1.0, 1.2, std::numbers::pi / 2, 0.3, {2, 8, 2});
  for (const char* name : {"inner", "outer", "theta0", "theta1", "bottom", "top", "body"})
    EXPECT_TRUE(mesh.has_group(name)) << name;
  for (int n : mesh.group("theta0").nodes) EXPECT_NEAR(mesh.nodes()[n][1], 0.0, 1e-14);
}

TEST_P(Meshes, MshRoundTripKeepsGroups)
{
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  Mesh mesh = box_mesh(GetParam(), Vec3(0, 0, 0), Vec3(1, 1, 1), {3, 2, 2});
  // A second, overlapping volume group (a "leaflet" inside the "body").
  std::vector<int> half;
  for (std::size_t e = 0; e < mesh.num_elements(); e += 2) half.push_back(static_cast<int>(e));
  mesh.add_volume_group("leaflet", half);
  const std::filesystem::path path = fmt::format("round_trip_{}_{}.msh", static_cast<int>(GetParam()), rank);
  write_msh(mesh, path);
  const Mesh back = read_msh(path);
  std::filesystem::remove(path);
  ASSERT_EQ(back.shape(), mesh.shape());
  ASSERT_EQ(back.num_elements(), mesh.num_elements());
  ASSERT_EQ(back.num_nodes(), mesh.num_nodes());
  EXPECT_NEAR(back.volume(), mesh.volume(), 1e-14);
  ASSERT_EQ(back.groups().size(), mesh.groups().size());
  // Nodes are renumbered by the reader: compare positions.
  for (const auto& group : mesh.groups()) {
    const PhysicalGroup& other = back.group(group.name);
    EXPECT_EQ(other.dimension, group.dimension) << group.name;
    EXPECT_EQ(other.elements.size(), group.elements.size()) << group.name;
    EXPECT_EQ(other.cells.size(), group.cells.size()) << group.name;
    ASSERT_EQ(other.nodes.size(), group.nodes.size()) << group.name;
    Vec3 sum_a = Vec3::Zero(), sum_b = Vec3::Zero();
    for (int n : group.nodes) sum_a += mesh.nodes()[n];
    for (int n : other.nodes) sum_b += back.nodes()[n];
    EXPECT_NEAR((sum_a - sum_b).norm(), 0.0, 1e-12) << group.name;
    if (group.dimension == 2) {
      EXPECT_NEAR(surface_area(back, group.name), surface_area(mesh, group.name), 1e-14);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(HexAndTet, Meshes, ::testing::Values(CellShape::hexahedron, CellShape::tetrahedron));

TEST(MeshInput, MissingFileIsAnInputError)
{
  EXPECT_THROW(read_msh("no_such_mesh.msh"), ibvalve::InputError);
}

TEST(MeshInput, SubmeshKeepsItsGroups)
{
  const Mesh mesh = box_mesh(CellShape::hexahedron, Vec3(0, 0, 0), Vec3(2, 1, 1), {4, 2, 2});
  std::vector<int> left;
  for (std::size_t e = 0; e < mesh.num_elements(); ++e) {
    Vec3 c = Vec3::Zero();
    for (int n : mesh.element(e)) c += mesh.nodes()[n] / 8;
    if (c[0] < 1) left.push_back(static_cast<int>(e));
  }
  std::vector<int> map;
  const Mesh part = submesh(mesh, left, &map);
  EXPECT_NEAR(part.volume(), 1.0, 1e-14);
  EXPECT_TRUE(part.has_group("xmin"));
  EXPECT_FALSE(part.has_group("xmax"));
  EXPECT_NEAR(surface_area(part, "ymin"), 1.0, 1e-14);
  for (std::size_t n = 0; n < part.num_nodes(); ++n) EXPECT_EQ(part.nodes()[n], mesh.nodes()[map[n]]);
}

TEST(MeshInput, ReadsAMeshGmshGeneratedFromGeometry)
{
  // A mesh as users make them: an OpenCASCADE box meshed by gmsh into tetrahedra, with physical
  // groups on the volume, a face and a corner (nodes classified on points, curves and surfaces).
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  const std::filesystem::path path = fmt::format("gmsh_box_{}.msh", rank);
  Vec3 corner_position;
  {
    GmshSession session;
    gmsh::clear();
    gmsh::model::add("box");
    gmsh::model::occ::addBox(0, 0, 0, 2, 1, 0.5);
    gmsh::model::occ::synchronize();
    gmsh::option::setNumber("Mesh.MeshSizeMax", 0.25);
    const int body = gmsh::model::addPhysicalGroup(3, {1});
    gmsh::model::setPhysicalName(3, body, "body");
    // Face x = 0 of an OCC box is surface 1; point 1 is one of the box's corners.
    const int face = gmsh::model::addPhysicalGroup(2, {1});
    gmsh::model::setPhysicalName(2, face, "xmin");
    const int corner = gmsh::model::addPhysicalGroup(0, {1});
    gmsh::model::setPhysicalName(0, corner, "origin");
    double x0, y0, z0, x1, y1, z1;
    gmsh::model::getBoundingBox(0, 1, x0, y0, z0, x1, y1, z1);
    corner_position = Vec3(x0, y0, z0);
    gmsh::model::mesh::generate(3);
    gmsh::write(path.string());
    gmsh::clear();
  }
  const Mesh mesh = read_msh(path);
  std::filesystem::remove(path);
  EXPECT_EQ(mesh.shape(), CellShape::tetrahedron);
  EXPECT_NEAR(mesh.volume(), 1.0, 1e-12);
  EXPECT_EQ(mesh.group("body").elements.size(), mesh.num_elements());
  EXPECT_NEAR(surface_area(mesh, "xmin"), 0.5, 1e-12);
  for (int n : mesh.group("xmin").nodes) EXPECT_NEAR(mesh.nodes()[n][0], 0.0, 1e-12);
  ASSERT_EQ(mesh.group("origin").nodes.size(), 1u);
  EXPECT_NEAR((mesh.nodes()[mesh.group("origin").nodes[0]] - corner_position).norm(), 0.0, 1e-12);
}
