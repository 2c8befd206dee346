#pragma once
// An idealized tri-leaflet aortic valve in a straight tube, meshed with trilinear hexahedra.
//
// The published study (Zhu et al. 2021; docs/reference.md, "Geometry") gives the tube (inner radius 1.3 cm,
// wall 0.15 cm, length 13 cm) and the leaflet thickness (0.04 cm) but not the leaflet surface, so the valve
// here is parametric (docs/fe.md, "The aortic-valve mesh"):
//
// - The tube axis is z; the tube runs from z = 0 (inlet, left-ventricle side) to z = tube_length.
// - Three equal leaflets, each spanning 120 degrees less the free-edge gap, generated in the closed
//   state. A leaflet's mid-surface is P(u, s) with u in [-1, 1] across the leaflet (commissure to
//   commissure) and s in [0, 1] from the attachment to the free edge:
//     attachment A(u): on the tube's inner wall (the mid-surface meets the wall, so the leaflet's
//       outer half overlaps the tube, as an attached leaflet in the IB method may), z = base +
//       (commissure_height - commissure_strip) u^2 (a scallop with its nadir at the leaflet's centre), plus a
//       strip up the wall at each commissure (u = +-1) so that no element degenerates: the leaflet's end
//       columns are that strip's height from attachment to free edge (0.1 cm made slivers whose
//       corners folded: docs/fe.md, "The aortic-valve mesh");
//     free edge E(u): two straight segments from the commissures to the valve centre, each parallel to
//       a coaptation line (theta_k +- 60 degrees) in projection and free_edge_gap / 2 away from it,
//       descending from the commissures' height by free_edge_drop (1 - |u|) toward the centre (0: a
//       level free edge; a drop lengthens the free edge, the slack an opening valve needs to
//       reach the wall without stretching its fibers: 2 sqrt(c^2 + drop^2) against the level 2 c, c the
//       commissure-to-centre distance), so that neighbouring free edges (mid-surface) are free_edge_gap
//       apart: seen along the axis, the closed valve leaves three strips of that width open, an orifice of
//       about 3 tube_radius free_edge_gap (0.078 cm^2 by default) at most; near the free edge the leaflets
//       are tilted, so their thickness covers much of that in projection (neighbouring solids may
//       touch there, which the IB method allows);
//     P(u, s) = (1 - s) A(u) + s E(u) - sag sin(pi s) (1 - u^2) e_z: a belly bulging toward the
//       ventricle, as a closed valve under aortic pressure does.
//   The solid is the mid-surface extruded by +-thickness/2 along its normal.
// - Physical groups: "leaflet1".."leaflet3" (volumes); per leaflet "leafletK_attachment" (the faces
//   on the wall, tethered or held), "leafletK_tau1" / "leafletK_tau2" (the two halves of the attachment,
//   u < 0 and u > 0: FD2's Dirichlet surfaces), "leafletK_n1" / "leafletK_n2" (the nodes at the free
//   edge's ends, u = -1 and u = +1: FD1's Dirichlet points), "leafletK_free_edge",
//   "leafletK_commissure1" / "leafletK_commissure2" (the strips up the wall at u = -1 and u = +1: Dirichlet
//   surfaces that make FD2-type fibers circumferential, docs/fibers.md); "tube" (volume),
//   "tube_outer" (the tethered outer surface), "tube_inner", "tube_inlet", "tube_outlet".
#include <array>
#include <string>

#include "fe/mesh.hpp"

namespace ibvalve::fe {

// The defaults are the default valve case's (examples/aortic_valve/default.toml), and so the aortic-valve
// model's mesh.* keys' and `ibvalve mesh aortic-valve`'s: the study's radius, wall and leaflet thickness
// (docs/reference.md, "Geometry") around 5 cm of its 13 cm tube, the free edge's slack, and about one
// element per 0.125 cm grid cell (the study's tube and finer mesh: examples/aortic_valve/paper.toml).
struct ValveMeshParameters {
  // Geometry, cm.
  double tube_radius = 1.3;
  double tube_wall = 0.15;
  double tube_length = 5.25; ///< 2 cm below the valve's nadir, 2.05 cm above its commissures
  double leaflet_thickness = 0.04;
  double valve_base = 2.0;        ///< z of the attachment's nadir (leaflet centre), from the inlet
  double commissure_height = 1.2; ///< z of the commissures (and the closed free edge) above the nadir
  /// Height of the attachment strip up the wall at each commissure (see above).
  double commissure_strip = 0.3;
  double sag = 0.25;               ///< belly depth toward the ventricle
  double free_edge_drop = 0.5;     ///< how far the free edge descends from the commissures to the centre
  double free_edge_gap = 0.02;     ///< distance between neighbouring closed free edges (mid-surface)
  double first_leaflet_angle = 90; ///< degrees: direction of leaflet 1's centre about the axis
  // Resolution (elements).
  int leaflet_across = 24; ///< commissure to commissure (u); even
  int leaflet_radial = 10; ///< attachment to free edge (s)
  int leaflet_through = 1; ///< through the thickness
  int tube_around = 64;
  int tube_along = 40;
  int tube_through = 1;
  bool include_tube = true;
};

/// Checks the parameters (positive sizes, an even `leaflet_across`, a gap smaller than the radius ...)
/// and throws std::invalid_argument naming the parameter that is wrong.
void check(const ValveMeshParameters& parameters);

/// The valve (and tube) as one hexahedral mesh with the physical groups listed above.
Mesh aortic_valve_mesh(const ValveMeshParameters& parameters);

} // namespace ibvalve::fe
