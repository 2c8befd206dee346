#include "app/leaflet_state.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>

#include "base/errors.hpp"
#include "base/units.hpp"
#include "fe/quadrature_data.hpp"
#include "hemodynamics/geometry.hpp"

namespace ibvalve::app {

namespace {

using fe::Vec3;

/// The mean of the nodes within `tolerance` of the smallest `key`.
Vec3 mean_of_smallest(const fe::Mesh& mesh, const std::vector<int>& nodes, auto key, double tolerance)
{
  double smallest = std::numeric_limits<double>::infinity();
  for (int n : nodes) smallest = std::min(smallest, key(mesh.nodes()[n]));
  Vec3 sum = Vec3::Zero();
  int count = 0;
  for (int n : nodes)
    if (key(mesh.nodes()[n]) <= smallest + tolerance) {
      sum += mesh.nodes()[n];
      ++count;
    }
  return sum / count;
}

/// The leaflet's quadrature points within `radius` of `centre` in the reference configuration.
LeafletState::Sphere sphere(const fe::QuadratureData& quadrature, const std::vector<int>& elements,
                            const Vec3& centre, double radius)
{
  LeafletState::Sphere s{centre, {}, {}};
  const int points = quadrature.points_per_element();
  for (int e : elements)
    for (int q = 0; q < points; ++q)
      if ((quadrature.point(static_cast<std::size_t>(e), q) - centre).norm() <= radius) {
        s.points.push_back(static_cast<std::size_t>(e) * points + q);
        s.weights.push_back(quadrature.JxW(static_cast<std::size_t>(e), q));
      }
  return s;
}

} // namespace

LeafletState::LeafletState(const fe::SolidModel& solid, int leaflets, double thickness, double radius)
    : solid_(solid)
{
  const fe::Mesh& mesh = solid.mesh();
  auto axis_distance = [](const Vec3& x) { return std::hypot(x[0], x[1]); };
  auto height = [](const Vec3& x) { return x[2]; };
  for (int k = 1; k <= leaflets; ++k) {
    const std::string name = fmt::format("leaflet{}", k);
    const fe::PhysicalGroup& leaflet = mesh.group(name);
    const Vec3 top = mean_of_smallest(mesh, mesh.group(name + "_free_edge").nodes, axis_distance, thickness);
    const Vec3 nadir = mean_of_smallest(mesh, mesh.group(name + "_attachment").nodes, height, thickness);
    // The plane of symmetry holds the axis and the nadir: its normal is horizontal, across the nadir.
    const Vec3 normal = Vec3(-nadir[1], nadir[0], 0.0).normalized();
    double best = std::numeric_limits<double>::infinity();
    Vec3 belly = Vec3::Zero();
    for (int n : leaflet.nodes) {
      const Vec3& x = mesh.nodes()[n];
      const double score = std::abs((x - nadir).norm() - (x - top).norm()) + std::abs(normal.dot(x));
      if (score < best) {
        best = score;
        belly = x;
      }
    }
    belly_.push_back(sphere(solid.quadrature(), leaflet.elements, belly, radius));
    top_.push_back(sphere(solid.quadrature(), leaflet.elements, top, radius));
    if (belly_.back().points.empty() || top_.back().points.empty())
      throw InputError(fmt::format("aortic-valve: {}: no quadrature point lies within {} cm of its belly or "
                                   "top-centre (the mesh is too coarse for the study's spheres)",
                                   name, radius));
    nodes_.insert(nodes_.end(), leaflet.nodes.begin(), leaflet.nodes.end());
  }
  for (int n : nodes_) reference_.push_back({mesh.nodes()[n][0], mesh.nodes()[n][1], mesh.nodes()[n][2]});
}

std::vector<double> LeafletState::row(std::span<const double> displacement, double max_fluid_speed) const
{
  std::vector<hemodynamics::Point> current(nodes_.size());
  for (std::size_t i = 0; i < nodes_.size(); ++i)
    for (int d = 0; d < 3; ++d) current[i][d] = reference_[i][d] + displacement[3 * nodes_[i] + d];
  const hemodynamics::DisplacementStatistics moved =
      hemodynamics::displacement_statistics(reference_, current);
  const fe::PointFields fields = solid_.point_fields(displacement);
  // Per sphere the volume average; then the mean over the leaflets. The stress is f . (sigma f) with
  // f = F f0 (docs/reference.md), lambda_f^2 = 1 + 2 E_ff times the unit-fiber normal stress that
  // point_fields gives.
  auto average = [&](const std::vector<Sphere>& spheres, bool stress) {
    double over_leaflets = 0.0;
    for (const Sphere& s : spheres) {
      double value = 0.0, volume = 0.0;
      for (std::size_t i = 0; i < s.points.size(); ++i) {
        const std::size_t p = s.points[i];
        const double strain = fields.fiber_strain[p];
        value += s.weights[i] * (stress ? (1.0 + 2.0 * strain) * fields.fiber_stress[p] : strain);
        volume += s.weights[i];
      }
      over_leaflets += value / volume;
    }
    return over_leaflets / static_cast<double>(spheres.size());
  };
  return {moved.mean,
          moved.max,
          max_fluid_speed,
          average(belly_, false),
          average(top_, false),
          average(belly_, true) / units::kPa,
          average(top_, true) / units::kPa};
}

std::string LeafletState::describe() const
{
  std::string out = "leaflet spheres (reference centres, quadrature points inside):";
  for (std::size_t k = 0; k < belly_.size(); ++k)
    out += fmt::format(
        " leaflet{} belly ({:.3f}, {:.3f}, {:.3f}) {}, top-centre ({:.3f}, {:.3f}, {:.3f}) {};", k + 1,
        belly_[k].centre[0], belly_[k].centre[1], belly_[k].centre[2], belly_[k].points.size(),
        top_[k].centre[0], top_[k].centre[1], top_[k].centre[2], top_[k].points.size());
  out.pop_back();
  return out;
}

} // namespace ibvalve::app
