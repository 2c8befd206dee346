#include "ib/coupling_points.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include <Eigen/LU>

namespace ibvalve::ib {

CouplingPoints::CouplingPoints(const fe::Mesh& mesh, CouplingPointSettings settings)
    : mesh_(mesh), settings_(settings), per_direction_(mesh.num_elements(), 1),
      weight_cache_(mesh.num_elements())
{
  if (!(settings.spacing > 0.0) || settings.min_points < 1 || settings.max_points < settings.min_points)
    throw std::invalid_argument(
        "ib: coupling point spacing must be positive and 1 <= min_points <= max_points");
  // The cell's edges are the sides of its faces (each face lists its nodes around its boundary).
  std::set<std::pair<int, int>> edges;
  for (const auto& face : mesh.type().faces())
    for (std::size_t a = 0; a < face.size(); ++a) {
      const int i = face[a], j = face[(a + 1) % face.size()];
      edges.insert({std::min(i, j), std::max(i, j)});
    }
  edges_.assign(edges.begin(), edges.end());
}

const CouplingPoints::Rule& CouplingPoints::rule(int n)
{
  auto found = rules_.find(n);
  if (found != rules_.end()) return found->second;
  const fe::ElementType& type = mesh_.type();
  Rule r;
  // A Gauss rule with n points per direction is exact for degree 2n - 1 (tensor or conical product).
  r.rule = type.quadrature(2 * n - 1);
  const int nodes = type.num_nodes();
  r.values.resize(r.rule.size() * nodes);
  r.gradients.resize(r.rule.size() * nodes);
  for (std::size_t q = 0; q < r.rule.size(); ++q) {
    type.values(r.rule.points[q], std::span<double>(r.values.data() + q * nodes, nodes));
    type.gradients(r.rule.points[q], std::span<fe::Vec3>(r.gradients.data() + q * nodes, nodes));
  }
  return rules_.emplace(n, std::move(r)).first->second;
}

std::size_t CouplingPoints::update(std::span<const Vec3> positions, double h,
                                   std::span<const std::uint8_t> placed)
{
  const std::size_t elements = mesh_.num_elements();
  const int nodes = mesh_.nodes_per_element();
  if (!placed.empty() && placed.size() != elements)
    throw std::invalid_argument("ib: one placement flag per element is needed");
  std::size_t capped = 0;
  std::size_t total = 0;
  bool rules_changed = position_.empty();
  for (std::size_t e = 0; e < elements; ++e) {
    const auto element = mesh_.element(e);
    double longest = 0.0;
    for (const auto& [i, j] : edges_)
      longest = std::max(longest, (positions[element[i]] - positions[element[j]]).norm());
    const double wanted = std::ceil(longest / (settings_.spacing * h) - 1e-9);
    int n = static_cast<int>(std::clamp(wanted, 1.0, 1e6));
    if (n > settings_.max_points) ++capped;
    n = std::clamp(n, settings_.min_points, settings_.max_points);
    rules_changed = rules_changed || per_direction_[e] != n;
    per_direction_[e] = n;
    total += rule(n).rule.size();
  }
  if (rules_changed) {
    // The points' elements, shape values and reference weights depend on the rules alone: laid out
    // again only when an element's rule changed. On a deforming valve that is most placements (some
    // leaflet element's longest edge is always near a multiple of the spacing), so each element's
    // reference weights are computed once per rule it takes and then copied (reference_weights).
    position_.resize(total);
    first_point_.resize(elements + 1);
    element_.resize(total);
    weight_.resize(total);
    values_.resize(total);
    std::size_t q = 0;
    for (std::size_t e = 0; e < elements; ++e) {
      const int n = per_direction_[e];
      const Rule& r = rules_.at(n);
      const std::size_t weights = reference_weights(e, n);
      first_point_[e] = q;
      for (std::size_t p = 0; p < r.rule.size(); ++p, ++q) {
        element_[q] = e;
        weight_[q] = weight_pool_[weights + p];
        values_[q] = r.values.data() + p * nodes;
      }
    }
    first_point_[elements] = q;
  }
  for (std::size_t e = 0; e < elements; ++e) {
    if (!placed.empty() && placed[e] == 0) continue;
    const auto element = mesh_.element(e);
    for (std::size_t q = first_point_[e]; q < first_point_[e + 1]; ++q) {
      const double* N = values_[q];
      Vec3 x = Vec3::Zero();
      for (int a = 0; a < nodes; ++a) x += N[a] * positions[element[a]];
      position_[q] = x;
    }
  }
  return capped;
}

std::size_t CouplingPoints::reference_weights(std::size_t e, int n)
{
  for (const auto& [rule_points, offset] : weight_cache_[e])
    if (rule_points == n) return offset;
  // w_q det(dX/dxi) at the rule's points, from the element's reference nodes.
  const Rule& r = rule(n);
  const auto element = mesh_.element(e);
  const auto& X = mesh_.nodes();
  const int nodes = mesh_.nodes_per_element();
  const std::size_t offset = weight_pool_.size();
  for (std::size_t p = 0; p < r.rule.size(); ++p) {
    const fe::Vec3* dN = r.gradients.data() + p * nodes;
    Eigen::Matrix3d dXdxi = Eigen::Matrix3d::Zero();
    for (int a = 0; a < nodes; ++a) dXdxi += X[element[a]] * dN[a].transpose();
    weight_pool_.push_back(r.rule.weights[p] * dXdxi.determinant());
  }
  weight_cache_[e].emplace_back(n, offset);
  return offset;
}

std::span<const double> CouplingPoints::shape_values(std::size_t q) const
{
  return {values_[q], static_cast<std::size_t>(mesh_.nodes_per_element())};
}

void CouplingPoints::evaluate(std::span<const double> nodal, int components, std::span<Vec3> values) const
{
  const int nodes = mesh_.nodes_per_element();
  for (std::size_t q = 0; q < size(); ++q) {
    const auto element = mesh_.element(element_[q]);
    Vec3 v = Vec3::Zero();
    for (int a = 0; a < nodes; ++a)
      for (int c = 0; c < components; ++c) v[c] += values_[q][a] * nodal[components * element[a] + c];
    values[q] = v;
  }
}

void CouplingPoints::add_projection_rhs(std::span<const std::size_t> points, std::span<const Vec3> values,
                                        std::span<double> rhs) const
{
  const int nodes = mesh_.nodes_per_element();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::size_t q = points[i];
    const auto element = mesh_.element(element_[q]);
    const Vec3 g = values[i] * weight_[q];
    for (int a = 0; a < nodes; ++a)
      for (int c = 0; c < 3; ++c) rhs[3 * element[a] + c] += values_[q][a] * g[c];
  }
}

} // namespace ibvalve::ib
