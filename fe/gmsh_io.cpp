#include "fe/gmsh_io.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <map>
#include <mutex>
#include <set>
#include <unordered_map>

#include <gmsh.h>

#include "base/errors.hpp"
#include "io/files.hpp"

namespace ibvalve::fe {

namespace {

std::mutex gmsh_mutex;
int gmsh_users = 0;

std::string last_gmsh_error()
{
  std::string message;
  try {
    gmsh::logger::getLastError(message);
  } catch (...) {
  }
  return message.empty() ? "gmsh failed" : message;
}

} // namespace

GmshSession::GmshSession()
{
  std::lock_guard lock(gmsh_mutex);
  if (gmsh_users++ == 0) {
    gmsh::initialize(0, nullptr, false);
    gmsh::option::setNumber("General.Terminal", 0);
  }
}

GmshSession::~GmshSession()
{
  std::lock_guard lock(gmsh_mutex);
  if (--gmsh_users == 0) gmsh::finalize();
}

Mesh read_msh(const std::filesystem::path& path)
{
  if (!std::filesystem::exists(path)) throw InputError(path.string() + ": mesh file not found");
  io::check_input_file(path, io::max_mesh_bytes);
  GmshSession session;
  const std::string where = path.string() + ": ";
  try {
    gmsh::clear();
    gmsh::open(path.string());
  } catch (...) {
    throw InputError(where + "gmsh cannot read the mesh: " + last_gmsh_error());
  }

  std::vector<int> types;
  std::vector<std::vector<std::size_t>> element_tags, element_nodes;
  gmsh::model::mesh::getElements(types, element_tags, element_nodes, 3, -1);
  if (types.empty()) throw InputError(where + "the mesh has no 3-D elements");
  if (types.size() > 1)
    throw InputError(where + "mixed 3-D element types are not supported (one of tet4 or hex8)");
  CellShape shape;
  try {
    shape = shape_of_gmsh_type(types[0]);
  } catch (const std::exception& error) {
    throw InputError(where + error.what());
  }
  if (shape != CellShape::hexahedron && shape != CellShape::tetrahedron)
    throw InputError(where + "3-D elements must be first-order tetrahedra or hexahedra");

  std::vector<std::size_t> node_tags;
  std::vector<double> coordinates, parametric;
  gmsh::model::mesh::getNodes(node_tags, coordinates, parametric, -1, -1, false, false);
  std::unordered_map<std::size_t, std::size_t> position_of_tag;
  for (std::size_t i = 0; i < node_tags.size(); ++i) position_of_tag[node_tags[i]] = i;

  // Keep only the nodes of 3-D elements, numbered in order of first use.
  std::unordered_map<std::size_t, int> index_of_tag;
  std::vector<Vec3> nodes;
  std::vector<int> connectivity;
  for (std::size_t tag : element_nodes[0]) {
    auto [it, inserted] = index_of_tag.try_emplace(tag, static_cast<int>(nodes.size()));
    if (inserted) {
      const auto p = position_of_tag.find(tag);
      if (p == position_of_tag.end())
        throw InputError(where + "an element refers to a node that does not exist");
      nodes.emplace_back(coordinates[3 * p->second], coordinates[3 * p->second + 1],
                         coordinates[3 * p->second + 2]);
    }
    connectivity.push_back(it->second);
  }
  Mesh mesh(shape, std::move(nodes), std::move(connectivity));
  std::unordered_map<std::size_t, int> element_of_tag;
  for (std::size_t e = 0; e < element_tags[0].size(); ++e)
    element_of_tag[element_tags[0][e]] = static_cast<int>(e);

  gmsh::vectorpair groups;
  gmsh::model::getPhysicalGroups(groups, -1);
  for (const auto& [dim, tag] : groups) {
    PhysicalGroup group;
    group.dimension = dim;
    group.tag = tag;
    gmsh::model::getPhysicalName(dim, tag, group.name);
    if (group.name.empty()) group.name = fmt::format("{}d_{}", dim, tag);
    std::vector<int> entities;
    gmsh::model::getEntitiesForPhysicalGroup(dim, tag, entities);
    for (int entity : entities) {
      std::vector<int> entity_types;
      std::vector<std::vector<std::size_t>> tags, entity_nodes;
      gmsh::model::mesh::getElements(entity_types, tags, entity_nodes, dim, entity);
      for (std::size_t k = 0; k < entity_types.size(); ++k) {
        CellShape cell_shape;
        try {
          cell_shape = shape_of_gmsh_type(entity_types[k]);
        } catch (const std::exception& error) {
          throw InputError(where + "physical group '" + group.name + "': " + error.what());
        }
        if (dim == 3) {
          for (std::size_t t : tags[k]) group.elements.push_back(element_of_tag.at(t));
          continue;
        }
        if (!group.cells.empty() && cell_shape != group.cell_shape)
          throw InputError(where + "physical group '" + group.name + "' mixes cell types");
        group.cell_shape = cell_shape;
        for (std::size_t t : entity_nodes[k]) {
          const auto it = index_of_tag.find(t);
          if (it == index_of_tag.end())
            throw InputError(where + "physical group '" + group.name +
                             "' has a node that no 3-D element uses");
          group.cells.push_back(it->second);
        }
      }
    }
    if (mesh.has_group(group.name))
      throw InputError(where + "two physical groups are named '" + group.name + "'");
    mesh.add_group(std::move(group));
  }
  gmsh::clear();
  return mesh;
}

void write_msh(const Mesh& mesh, const std::filesystem::path& path)
{
  GmshSession session;
  gmsh::clear();
  gmsh::model::add("ibvalve");
  gmsh::option::setNumber("Mesh.MshFileVersion", 4.1);
  gmsh::option::setNumber("Mesh.Binary", 0);
  gmsh::option::setNumber("Mesh.SaveAll", 0);

  // One volume entity per distinct set of volume groups (the groups an element belongs to).
  std::vector<const PhysicalGroup*> volume_groups;
  for (const auto& g : mesh.groups())
    if (g.dimension == 3) volume_groups.push_back(&g);
  std::vector<std::vector<int>> membership(mesh.num_elements());
  for (std::size_t v = 0; v < volume_groups.size(); ++v)
    for (int e : volume_groups[v]->elements) membership[e].push_back(static_cast<int>(v));
  std::map<std::vector<int>, std::vector<int>> elements_of_signature;
  for (std::size_t e = 0; e < mesh.num_elements(); ++e)
    elements_of_signature[membership[e]].push_back(static_cast<int>(e));

  std::vector<std::size_t> node_tags(mesh.num_nodes());
  std::vector<double> coordinates;
  for (std::size_t n = 0; n < mesh.num_nodes(); ++n) {
    node_tags[n] = n + 1;
    for (int d = 0; d < 3; ++d) coordinates.push_back(mesh.nodes()[n][d]);
  }

  std::size_t next_element_tag = 1;
  int next_entity[4] = {1, 1, 1, 1};
  std::vector<std::vector<int>> entities_of_volume_group(volume_groups.size());
  bool nodes_added = false;
  for (const auto& [signature, elements] : elements_of_signature) {
    const int entity = gmsh::model::addDiscreteEntity(3, next_entity[3]++);
    if (!nodes_added) {
      // Every node lives on the first volume entity; other entities' elements refer to them.
      gmsh::model::mesh::addNodes(3, entity, node_tags, coordinates);
      nodes_added = true;
    }
    std::vector<std::size_t> tags, nodes;
    for (int e : elements) {
      tags.push_back(next_element_tag++);
      for (int n : mesh.element(e)) nodes.push_back(static_cast<std::size_t>(n) + 1);
    }
    gmsh::model::mesh::addElementsByType(entity, mesh.type().gmsh_type(), tags, nodes);
    for (int v : signature) entities_of_volume_group[v].push_back(entity);
  }

  std::set<int> used_tags[4];
  for (const auto& g : mesh.groups())
    if (g.tag > 0) used_tags[g.dimension].insert(g.tag);
  auto physical_tag = [&](const PhysicalGroup& g) {
    if (g.tag > 0) return g.tag;
    int t = 1;
    while (used_tags[g.dimension].count(t)) ++t;
    used_tags[g.dimension].insert(t);
    return t;
  };
  for (std::size_t v = 0; v < volume_groups.size(); ++v) {
    const int tag =
        gmsh::model::addPhysicalGroup(3, entities_of_volume_group[v], physical_tag(*volume_groups[v]));
    gmsh::model::setPhysicalName(3, tag, volume_groups[v]->name);
  }
  for (const auto& g : mesh.groups()) {
    if (g.dimension == 3) continue;
    const int entity = gmsh::model::addDiscreteEntity(g.dimension, next_entity[g.dimension]++);
    const int k = nodes_per_cell(g.cell_shape);
    std::vector<std::size_t> tags, nodes;
    for (std::size_t c = 0; c < g.cells.size(); c += k) {
      tags.push_back(next_element_tag++);
      for (int i = 0; i < k; ++i) nodes.push_back(static_cast<std::size_t>(g.cells[c + i]) + 1);
    }
    gmsh::model::mesh::addElementsByType(entity, gmsh_type_of(g.cell_shape), tags, nodes);
    const int tag = gmsh::model::addPhysicalGroup(g.dimension, {entity}, physical_tag(g));
    gmsh::model::setPhysicalName(g.dimension, tag, g.name);
  }
  // Elements in no volume group must still be written.
  if (elements_of_signature.count({})) gmsh::option::setNumber("Mesh.SaveAll", 1);
  try {
    gmsh::write(path.string());
  } catch (...) {
    throw InputError(path.string() + ": cannot write the mesh: " + last_gmsh_error());
  }
  gmsh::clear();
}

} // namespace ibvalve::fe
