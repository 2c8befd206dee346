#pragma once
// The leaflets' state in each time-series row of the aortic-valve model: what the study's structural
// figures are read from (docs/reference.md, "Hemodynamic metrics"; the columns and metrics:
// hemodynamics/timeseries.hpp and docs/hemodynamics.md, "Leaflet state").
//
// Per row: the mean and largest leaflet displacement, the peak velocity (app/jet_region.hpp), and the fiber
// strain f0 . (E f0) and fiber stress f . (sigma f) (f = F f0) averaged over spheres of radius 0.15 cm at
// each leaflet's belly and top-centre, then over the leaflets. The spheres are material regions: the
// quadrature points of the leaflet whose reference position lies inside, weighted by their volume.
// Their centres come from the mesh's groups, so any mesh with the generator's groups gets them:
//  - top-centre: the middle of the free edge, the mean of the leafletK_free_edge nodes within one
//    leaflet thickness of the one nearest the tube's axis;
//  - belly: in the leaflet's plane of symmetry (through the axis and the attachment's nadir, the mean of
//    the leafletK_attachment nodes within one thickness of the lowest), the leaflet node as far along
//    the leaflet from the nadir as from the top-centre (both distances equal, the node nearest that
//    plane breaking ties).
#include <array>
#include <span>
#include <string>
#include <vector>

#include "fe/mesh.hpp"
#include "fe/solid.hpp"

namespace ibvalve::app {

class LeafletState {
 public:
  /// The leaflets are the volume groups "leaflet1".."leafletN"; `thickness` (cm) sets the tolerances
  /// above; `radius` is the spheres' (cm).
  LeafletState(const fe::SolidModel& solid, int leaflets, double thickness, double radius = 0.15);

  /// The row's values, in the order and units of hemodynamics::leaflet_state_columns() (cm, cm/s,
  /// kPa). Collective: every rank passes the same displacement and gets the same values.
  std::vector<double> row(std::span<const double> displacement, double max_fluid_speed) const;

  /// Sphere centres (reference configuration, cm), one per leaflet, and the quadrature points each
  /// holds: for the log and the tests.
  struct Sphere {
    fe::Vec3 centre;
    std::vector<std::size_t> points; ///< indices e * points_per_element + q
    std::vector<double> weights;     ///< their reference volumes
  };
  const std::vector<Sphere>& belly() const { return belly_; }
  const std::vector<Sphere>& top() const { return top_; }
  std::string describe() const;

 private:
  const fe::SolidModel& solid_;
  std::vector<int> nodes_;                       ///< every leaflet node
  std::vector<std::array<double, 3>> reference_; ///< their reference positions
  std::vector<Sphere> belly_, top_;
};

} // namespace ibvalve::app
