#pragma once
// The points where the structure meets the grid: per element a tensor Gauss rule (a conical product
// rule on tetrahedra) with n points per direction, n chosen from the element's current size so that
// neighbouring points stay about `spacing` grid cells apart or closer (Griffith & Luo 2017, Int. J.
// Numer. Meth. Biomed. Engng. 33:e2888, section 3.3: too few points per cell let fluid leak through
// the structure, too many only cost time). The rule is chosen again every time the points move.
//
// Each point carries its element, its shape function values and its reference weight w_q det(dX/dxi),
// so a nodal field is evaluated at the points as sum_a N_a(X_q) V_a, and point data g_q becomes the
// L2-projection right-hand side b_a = sum_q N_a(X_q) g_q w_q.
#include <cstdint>
#include <map>
#include <span>
#include <vector>

#include "fe/mesh.hpp"
#include "fe/quadrature.hpp"

namespace ibvalve::ib {

using Vec3 = Eigen::Vector3d;

struct CouplingPointSettings {
  double spacing = 0.5; ///< the largest point spacing, in grid cells (the smallest cell side)
  int min_points = 1;   ///< per direction
  int max_points = 16;  ///< per direction (a very stretched element is capped, and reported)
};

class CouplingPoints {
 public:
  CouplingPoints(const fe::Mesh& mesh, CouplingPointSettings settings);

  /// Chooses each element's rule from its current edge lengths (`positions`: one per node) and the
  /// grid spacing `h`, and places the points. Returns the number of elements whose rule was capped.
  /// With `placed` (one flag per element) only the points of the flagged elements are placed, and
  /// the others' positions() are not meaningful (a rank places only the points it may handle).
  std::size_t update(std::span<const Vec3> positions, double h, std::span<const std::uint8_t> placed = {});

  std::size_t size() const { return position_.size(); }
  std::span<const Vec3> positions() const { return position_; }
  std::size_t element(std::size_t q) const { return element_[q]; }
  /// w_q det(dX/dxi) at point q (the reference volume the point stands for).
  double weight(std::size_t q) const { return weight_[q]; }
  /// N_a at point q, a = 0 .. nodes_per_element-1.
  std::span<const double> shape_values(std::size_t q) const;
  /// Points per direction of element e's current rule.
  int points_per_direction(std::size_t e) const { return per_direction_[e]; }
  /// The points of element e are the indices [first_point(e), first_point(e + 1)).
  std::size_t first_point(std::size_t e) const { return first_point_[e]; }

  /// The values of a nodal field (`components` per node, interlaced) at every point.
  void evaluate(std::span<const double> nodal, int components, std::span<Vec3> values) const;
  /// Adds b_a += N_a(X_q) w_q g_q for the listed points (3 components, interlaced).
  void add_projection_rhs(std::span<const std::size_t> points, std::span<const Vec3> values,
                          std::span<double> rhs) const;

 private:
  struct Rule {
    fe::QuadratureRule rule;
    std::vector<double> values;      // points x nodes
    std::vector<fe::Vec3> gradients; // points x nodes, dN/dxi
  };
  const Rule& rule(int n);
  /// Where element e's reference weights for the rule with n points per direction start in
  /// weight_pool_, computed the first time the element takes that rule.
  std::size_t reference_weights(std::size_t e, int n);

  const fe::Mesh& mesh_;
  CouplingPointSettings settings_;
  std::vector<std::pair<int, int>> edges_; // local node pairs of the cell's edges
  std::map<int, Rule> rules_;
  std::vector<int> per_direction_;
  std::vector<std::size_t> first_point_; // elements + 1 offsets into the point arrays
  std::vector<Vec3> position_;
  std::vector<std::size_t> element_;
  std::vector<double> weight_;
  std::vector<const double*> values_;
  std::vector<std::vector<std::pair<int, std::size_t>>> weight_cache_; // per element: (n, offset)
  std::vector<double> weight_pool_;
};

} // namespace ibvalve::ib
