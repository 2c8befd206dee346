#include "app/jet_region.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <stdexcept>

#include "hemodynamics/report.hpp"

namespace ibvalve::app {

bool JetRegion::contains(const fluid::Real3& x) const
{
  return std::hypot(x[0], x[1]) <= radius && x[2] >= lower && x[2] <= upper;
}

fluid::PointSet JetRegion::points() const
{
  return [region = *this](const fluid::Real3& x) { return region.contains(x); };
}

std::string JetRegion::describe() const
{
  return fmt::format("peak velocity (u_max) in the tube (r <= {} cm) at {} <= z <= {} cm, between the "
                     "pressure probes",
                     hemodynamics::format_value(radius), hemodynamics::format_value(lower),
                     hemodynamics::format_value(upper));
}

JetRegion jet_region(double lower_probe, double upper_probe, double tube_radius,
                     const fluid::BoxGeometry& box, int side_cells)
{
  const double margin = side_cells * box.spacing(2);
  JetRegion region{tube_radius, std::max(lower_probe, box.lower[2] + margin),
                   std::min(upper_probe, box.upper[2] - margin)};
  if (!(region.lower < region.upper) || !(tube_radius > 0.0))
    throw std::invalid_argument(fmt::format("no jet region between the probes at z = {} and {} cm within the "
                                            "box's z range [{}, {}] cm less {} cells at each end",
                                            lower_probe, upper_probe, box.lower[2], box.upper[2],
                                            side_cells));
  return region;
}

} // namespace ibvalve::app
