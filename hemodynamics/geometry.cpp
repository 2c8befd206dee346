#include "hemodynamics/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace ibvalve::hemodynamics {

namespace {

Eigen::Vector3d vec(const Point& p)
{
  return {p[0], p[1], p[2]};
}

/// Marks the pixels whose centres lie in the 2-D triangle (a, b, c), by scanlines: each pixel row's
/// centre line cuts the triangle in one interval, whose pixel centres are covered.
void fill_triangle(std::vector<unsigned char>& covered, int n, double lo, double pixel,
                   const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c)
{
  const double ymin = std::min({a.y(), b.y(), c.y()}), ymax = std::max({a.y(), b.y(), c.y()});
  const int row0 = std::max(0, static_cast<int>(std::ceil((ymin - lo) / pixel - 0.5)));
  const int row1 = std::min(n - 1, static_cast<int>(std::floor((ymax - lo) / pixel - 0.5)));
  const std::array<std::pair<Eigen::Vector2d, Eigen::Vector2d>, 3> edges{{{a, b}, {b, c}, {c, a}}};
  for (int row = row0; row <= row1; ++row) {
    const double y = lo + (row + 0.5) * pixel;
    double xmin = std::numeric_limits<double>::infinity(), xmax = -xmin;
    for (const auto& [p, q] : edges) {
      if ((p.y() <= y && y <= q.y()) || (q.y() <= y && y <= p.y())) {
        if (p.y() == q.y()) {
          xmin = std::min({xmin, p.x(), q.x()});
          xmax = std::max({xmax, p.x(), q.x()});
        } else {
          const double x = p.x() + (y - p.y()) / (q.y() - p.y()) * (q.x() - p.x());
          xmin = std::min(xmin, x);
          xmax = std::max(xmax, x);
        }
      }
    }
    if (!(xmin <= xmax)) continue;
    const int col0 = std::max(0, static_cast<int>(std::ceil((xmin - lo) / pixel - 0.5)));
    const int col1 = std::min(n - 1, static_cast<int>(std::floor((xmax - lo) / pixel - 0.5)));
    for (int col = col0; col <= col1; ++col) covered[static_cast<std::size_t>(row) * n + col] = 1;
  }
}

} // namespace

double geometric_orifice_area(std::span<const Point> points, std::span<const Triangle> triangles,
                              std::span<const Quad> quads, const CrossSection& section,
                              const OrificeOptions& options)
{
  if (options.resolution < 8) throw std::invalid_argument("orifice area: resolution must be >= 8");
  if (!(section.radius > 0.0)) throw std::invalid_argument("orifice area: radius must be positive");
  Eigen::Vector3d axis = vec(section.axis);
  if (axis.norm() == 0.0) throw std::invalid_argument("orifice area: zero axis");
  axis.normalize();
  // An orthonormal basis (e1, e2) of the cross-section plane.
  const Eigen::Vector3d helper =
      std::abs(axis.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d e1 = axis.cross(helper).normalized();
  const Eigen::Vector3d e2 = axis.cross(e1);
  const Eigen::Vector3d centre = vec(section.centre);
  std::vector<Eigen::Vector2d> projected(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d d = vec(points[i]) - centre;
    projected[i] = {d.dot(e1), d.dot(e2)};
  }
  const int n = options.resolution;
  const double r = section.radius, lo = -r, pixel = 2.0 * r / n;
  std::vector<unsigned char> covered(static_cast<std::size_t>(n) * n, 0);
  auto check = [&](std::size_t index) {
    if (index >= points.size())
      throw std::invalid_argument("orifice area: a face names a node that does not exist");
    return projected[index];
  };
  for (const Triangle& t : triangles)
    fill_triangle(covered, n, lo, pixel, check(t[0]), check(t[1]), check(t[2]));
  for (const Quad& q : quads) {
    fill_triangle(covered, n, lo, pixel, check(q[0]), check(q[1]), check(q[2]));
    fill_triangle(covered, n, lo, pixel, check(q[0]), check(q[2]), check(q[3]));
  }
  std::size_t open = 0;
  for (int row = 0; row < n; ++row) {
    const double y = lo + (row + 0.5) * pixel;
    for (int col = 0; col < n; ++col) {
      const double x = lo + (col + 0.5) * pixel;
      if (x * x + y * y <= r * r && !covered[static_cast<std::size_t>(row) * n + col]) ++open;
    }
  }
  return static_cast<double>(open) * pixel * pixel;
}

DisplacementStatistics displacement_statistics(std::span<const Point> reference,
                                               std::span<const Point> current)
{
  if (reference.size() != current.size()) throw std::invalid_argument("displacement: sizes differ");
  DisplacementStatistics s;
  if (reference.empty()) return s;
  double sum = 0.0;
  for (std::size_t i = 0; i < reference.size(); ++i) {
    const double d = (vec(current[i]) - vec(reference[i])).norm();
    sum += d;
    s.max = std::max(s.max, d);
  }
  s.mean = sum / static_cast<double>(reference.size());
  return s;
}

RegionAverage sphere_average(std::span<const Point> points, std::span<const double> values,
                             std::span<const double> weights, const Point& centre, double radius)
{
  if (values.size() != points.size() || (!weights.empty() && weights.size() != points.size()))
    throw std::invalid_argument("sphere average: points, values and weights differ in size");
  RegionAverage out;
  double sum = 0.0;
  const Eigen::Vector3d c = vec(centre);
  for (std::size_t i = 0; i < points.size(); ++i) {
    if ((vec(points[i]) - c).squaredNorm() > radius * radius) continue;
    const double w = weights.empty() ? 1.0 : weights[i];
    sum += w * values[i];
    out.weight += w;
    ++out.count;
  }
  out.mean = out.weight > 0.0 ? sum / out.weight : std::numeric_limits<double>::quiet_NaN();
  return out;
}

double fiber_strain(const Eigen::Matrix3d& F, const Eigen::Vector3d& f0)
{
  const Eigen::Matrix3d E = 0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity());
  return f0.dot(E * f0);
}

double fiber_stress(const Eigen::Matrix3d& sigma, const Eigen::Matrix3d& F, const Eigen::Vector3d& f0)
{
  const Eigen::Vector3d f = F * f0;
  return f.dot(sigma * f);
}

} // namespace ibvalve::hemodynamics
