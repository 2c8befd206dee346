#pragma once
// Where the aortic-valve model measures the peak velocity of each time-series row (u_max, the report's
// peak_velocity_*): the valve's jet, not the whole box (docs/hemodynamics.md, "Peak velocity").
//
// The region is the tube's lumen between the two pressure probes the TPG is read from (P_nlv below the
// nadir, P_nao above the commissures): the stretch of flow whose pressure drop the TPG measures, and
// which holds the forward jet's vena contracta and the closed valve's regurgitant jet. Its ends keep
// `side_cells` cell layers from the box's inlet and outlet sides: where a pressure side lets fluid out,
// the last cell layer carries speeds no jet has (in the default run 386 cm/s there against 304 cm/s in
// the jet).
#include <string>

#include "fluid/boundary.hpp"
#include "fluid/grid.hpp"

namespace ibvalve::app {

struct JetRegion {
  double radius = 0.0;             ///< cm: the tube's inner radius, about the z axis
  double lower = 0.0, upper = 0.0; ///< z, cm

  bool contains(const fluid::Real3& x) const;
  /// The region as FlowSolver::max_speed_in takes it.
  fluid::PointSet points() const;
  /// "peak velocity in the tube (r <= 1.3 cm) at 1 <= z <= 4.2 cm, between the pressure probes".
  std::string describe() const;
};

/// The region between the probes at z = `lower_probe` and `upper_probe` (cm) within `tube_radius`, its
/// ends kept `side_cells` cell layers inside `box` along z. std::invalid_argument when nothing is left.
JetRegion jet_region(double lower_probe, double upper_probe, double tube_radius,
                     const fluid::BoxGeometry& box, int side_cells = 2);

} // namespace ibvalve::app
