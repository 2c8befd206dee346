#include "app/valve_mesh.hpp"

#include <fmt/format.h>

#include "app/resource_estimate.hpp"

namespace ibvalve::app {

void bind(io::KeyBinder& keys, ValveMeshKeys& k)
{
  keys.path("mesh.file",
            "a Gmsh mesh of one's own with the groups a valve run reads (docs/own-valve.md), relative to the "
            "case file (to the working folder in --set); unset = generate it from the keys below",
            k.file);
  const std::string file = keys.key_of(k.file);
  const fe::ValveMeshParameters d;
  fe::ValveMeshParameters& g = k.geometry;
  keys.real("mesh.tube_radius", "tube inner radius (the pressure disks and the flow plane)", g.tube_radius)
      .unit("cm")
      .defaults(d.tube_radius)
      .positive()
      .typical(0.5, 3.0, "an aortic root is about 1.2 cm; 10 times more is a value in mm");
  keys.real("mesh.tube_wall", "tube wall thickness", g.tube_wall).unit("cm").defaults(d.tube_wall).positive();
  keys.real("mesh.tube_length", "tube length", g.tube_length)
      .unit("cm")
      .defaults(d.tube_length)
      .positive()
      .typical(1.0, 30.0, "a few aortic root radii; 10 times more is a value in mm")
      .unused_with(file);
  keys.real("mesh.leaflet_thickness", "leaflet thickness (the leaflet state's spheres)", g.leaflet_thickness)
      .unit("cm")
      .defaults(d.leaflet_thickness)
      .positive();
  keys.real("mesh.valve_base", "z of the attachment's nadir (the probes and the flow plane)", g.valve_base)
      .unit("cm")
      .defaults(d.valve_base)
      .positive();
  keys.real("mesh.commissure_height", "commissures above the nadir (the probe above the valve)",
            g.commissure_height)
      .unit("cm")
      .defaults(d.commissure_height)
      .positive();
  keys.real("mesh.commissure_strip",
            "height of the attachment strip up the wall at each commissure, where a leaflet's attachment and "
            "free edge meet: the height of the leaflet's end columns of elements (docs/fe.md, \"The "
            "aortic-valve mesh\")",
            g.commissure_strip)
      .unit("cm")
      .defaults(d.commissure_strip)
      .positive()
      .unused_with(file);
  keys.real("mesh.sag", "belly depth toward the ventricle", g.sag)
      .unit("cm")
      .defaults(d.sag)
      .non_negative()
      .unused_with(file);
  keys.real("mesh.free_edge_drop",
            "how far the free edge descends from the commissures to the valve centre (slack for opening)",
            g.free_edge_drop)
      .unit("cm")
      .defaults(d.free_edge_drop)
      .non_negative()
      .unused_with(file);
  keys.real("mesh.free_edge_gap", "gap between closed free edges", g.free_edge_gap)
      .unit("cm")
      .defaults(d.free_edge_gap)
      .positive()
      .unused_with(file);
  keys.integer("mesh.leaflet_across", "leaflet elements commissure to commissure (even)", g.leaflet_across)
      .defaults(std::int64_t{d.leaflet_across})
      .at_most(max_mesh_cells)
      .unused_with(file);
  keys.integer("mesh.leaflet_radial", "leaflet elements attachment to free edge", g.leaflet_radial)
      .defaults(std::int64_t{d.leaflet_radial})
      .at_most(max_mesh_cells)
      .unused_with(file);
  keys.integer("mesh.tube_around", "tube elements around", g.tube_around)
      .defaults(std::int64_t{d.tube_around})
      .at_most(max_mesh_cells)
      .unused_with(file);
  keys.integer("mesh.tube_along", "tube elements along", g.tube_along)
      .defaults(std::int64_t{d.tube_along})
      .at_most(max_mesh_cells)
      .unused_with(file);
}

std::vector<ValveMeshGroup> required_valve_groups(int leaflets, fibers::FiberRule rule, bool tube,
                                                  const std::vector<std::string>& tethered,
                                                  const std::string& tethered_key)
{
  std::vector<ValveMeshGroup> groups;
  for (int k = 1; k <= leaflets; ++k) {
    const std::string leaflet = fmt::format("leaflet{}", k);
    groups.push_back({leaflet, true, "the leaflet's elements: leaflets.material, its fiber field"});
    groups.push_back({leaflet + "_attachment", false, "held by the attachment tether"});
    groups.push_back({leaflet + "_free_edge", false, "the leaflet state's top-centre sphere"});
    if (rule == fibers::FiberRule::FD1) {
      groups.push_back({leaflet + "_n1", false, "FD1's point u = 1, one end of the free edge"});
      groups.push_back({leaflet + "_n2", false, "FD1's point u = 0, the other end"});
    }
  }
  if (!tube) return groups;
  groups.push_back({"tube", true, "the tube's elements: tube.material"});
  for (const std::string& surface : tethered)
    groups.push_back({surface, false, "held in place: " + tethered_key});
  return groups;
}

std::string missing_groups(const fe::Mesh& mesh, const std::vector<ValveMeshGroup>& required)
{
  std::string list;
  std::size_t count = 0;
  for (const ValveMeshGroup& g : required) {
    std::string why;
    if (!mesh.has_group(g.name))
      why = g.volume ? "volume group; " + g.use : g.use;
    else if (g.volume && mesh.group(g.name).dimension != 3)
      why = "not a volume group; " + g.use;
    if (why.empty()) continue;
    list += fmt::format("{}{} ({})", list.empty() ? "" : ", ", g.name, why);
    ++count;
  }
  if (count == 0) return "";
  return fmt::format("the mesh lacks {} group{} a valve run reads (docs/own-valve.md): {}", count,
                     count == 1 ? "" : "s", list);
}

GeneratedSize generated_size(const fe::ValveMeshParameters& g, int leaflets)
{
  // Hexahedra of the leaflets and the tube, one layer through each (two layers of nodes).
  const double leaflet = static_cast<double>(leaflets) * g.leaflet_across * g.leaflet_radial,
               tube = g.include_tube ? static_cast<double>(g.tube_around) * g.tube_along : 0.0;
  const double nodes = 2.0 * (leaflets * (g.leaflet_across + 1.0) * (g.leaflet_radial + 1.0) +
                              (g.include_tube ? g.tube_around * (g.tube_along + 1.0) : 0.0));
  return {leaflet + tube, nodes, tube > leaflet};
}

std::vector<materials::FiberFrame> leaflet_fibers(const fe::Mesh& mesh, fibers::FiberRule rule, int leaflets,
                                                  MPI_Comm comm)
{
  std::vector<fibers::LeafletSpec> specs(static_cast<std::size_t>(leaflets));
  for (int k = 1; k <= leaflets; ++k)
    specs[static_cast<std::size_t>(k - 1)].group = fmt::format("leaflet{}", k);
  const fibers::FiberField field = fibers::compute_fibers(mesh, rule, specs, comm);
  std::vector<materials::FiberFrame> frames(mesh.num_elements());
  for (std::size_t e = 0; e < frames.size(); ++e) frames[e].f0 = field.element_directions[e];
  return frames;
}

std::string describe_valve_mesh(const ValveMeshKeys& keys, const fe::Mesh& mesh, int leaflets)
{
  std::size_t in_leaflets = 0;
  for (int k = 1; k <= leaflets; ++k) in_leaflets += mesh.group(fmt::format("leaflet{}", k)).elements.size();
  const std::string source = keys.file.empty() ? "generated" : keys.file.string();
  return fmt::format("mesh: {} ({} {}, {} in the leaflets, {} in the tube; {} nodes)", source,
                     mesh.num_elements(),
                     mesh.shape() == fe::CellShape::hexahedron ? "hexahedra" : "tetrahedra", in_leaflets,
                     mesh.has_group("tube") ? mesh.group("tube").elements.size() : 0, mesh.num_nodes());
}

} // namespace ibvalve::app
