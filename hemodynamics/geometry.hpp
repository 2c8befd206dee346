#pragma once
// Leaflet geometry measures from plain arrays (no fe/ dependency): the geometric orifice area, leaflet
// displacement, and regional averages of fiber strain and stress over small spheres.
#include <array>
#include <cstddef>
#include <span>

#include <Eigen/Dense>

namespace ibvalve::hemodynamics {

using Point = std::array<double, 3>;
using Triangle = std::array<std::size_t, 3>;
using Quad = std::array<std::size_t, 4>;

/// The tube's cross-section at the valve: a disc of `radius` about `centre`, normal to `axis`.
struct CrossSection {
  Point centre{0.0, 0.0, 0.0};
  Point axis{0.0, 0.0, 1.0};
  double radius = 1.3; // cm, the reference tube's inner radius
};

/// Geometric orifice area: the area of the cross-section disc NOT covered by the projection of the
/// leaflet surfaces along the axis. Computed by rasterising: the disc's bounding square is split into
/// `resolution` x `resolution` pixels, a pixel counts as open when its centre is inside the disc and
/// inside no projected triangle (quads are split into two triangles). The error is of the order of
/// one pixel row along the boundaries, about (perimeter of the open region) x (pixel size) / 4;
/// at the default 1024 it is below 0.1 % of the tube area for smooth openings (measured in
/// tests/hemodynamics). Units follow the points' (cm -> cm^2).
struct OrificeOptions {
  int resolution = 1024;
};
double geometric_orifice_area(std::span<const Point> points, std::span<const Triangle> triangles,
                              std::span<const Quad> quads, const CrossSection& section,
                              const OrificeOptions& options = {});

/// Mean and maximum |x - X| over the nodes.
struct DisplacementStatistics {
  double mean = 0.0;
  double max = 0.0;
};
DisplacementStatistics displacement_statistics(std::span<const Point> reference,
                                               std::span<const Point> current);

/// The weighted mean of `values` over the points within `radius` of `centre` (weights may be empty:
/// all 1; quadrature weights make it a volume average). `count` is the number of points used; the
/// mean is NaN when no point lies inside.
struct RegionAverage {
  double mean = 0.0;
  std::size_t count = 0;
  double weight = 0.0;
};
RegionAverage sphere_average(std::span<const Point> points, std::span<const double> values,
                             std::span<const double> weights, const Point& centre, double radius);

/// f0 . (E f0) with E = (F^T F - I) / 2, the Green–Lagrange strain along the reference fiber f0
/// (unit vector): (I4 - 1) / 2.
double fiber_strain(const Eigen::Matrix3d& F, const Eigen::Vector3d& f0);
/// f . (sigma f) with f = F f0 (as docs/reference.md, "Hemodynamic metrics", defines it: f is not
/// normalised, so this is lambda_f^2 times the Cauchy normal stress along the current fiber direction).
double fiber_stress(const Eigen::Matrix3d& sigma, const Eigen::Matrix3d& F, const Eigen::Vector3d& f0);

} // namespace ibvalve::hemodynamics
