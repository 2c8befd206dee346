#pragma once
// Where a flux is measured: a disk or a rectangle in a plane normal to a grid direction.
#include "fluid/grid.hpp"

namespace ibvalve::fluid {

/// A disk or a rectangle in a plane normal to x, y or z, at `position` along the normal (a box side
/// or any interior plane). The flux counts flow in the +normal direction.
struct PlaneRegion {
  enum class Shape { disk, rectangle };
  int normal = 0;
  double position = 0.0;
  Shape shape = Shape::disk;
  Real3 center{};         // disk: centre (its normal coordinate is ignored)
  double radius = 0.0;    // disk
  Real3 lower{}, upper{}; // rectangle: corners (normal coordinates ignored)

  static PlaneRegion disk(int normal, double position, Real3 center, double radius);
  static PlaneRegion rectangle(int normal, double position, Real3 lower, Real3 upper);
  /// The part of the axis-aligned square [a0,a1] x [b0,b1] (in the plane's two tangential
  /// coordinates, in order (normal+1)%3, (normal+2)%3) inside the region, as a fraction.
  double covered_fraction(double a0, double a1, double b0, double b1) const;
};

} // namespace ibvalve::fluid
