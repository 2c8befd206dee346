#pragma once
// Reference-configuration data at the quadrature points of every element, computed once per mesh:
// shape values N_a, gradients grad_X N_a = J^{-T} grad_xi N_a, and weights w_q det J_q. Force,
// tangent, mass and projection loops read from here instead of recomputing the geometry.
#include <span>
#include <vector>

#include <mpi.h>

#include "fe/mesh.hpp"

namespace ibvalve::fe {

// gradients(e, q) is read as a 3 x n column-major matrix (Eigen::Map) by the assembly loops.
static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 must be three packed doubles");

class QuadratureData {
 public:
  /// A rule exact for polynomials of degree `degree` on the reference cell. InputError when an
  /// element has a non-positive Jacobian (inverted or degenerate) at a quadrature point.
  QuadratureData(const Mesh& mesh, int degree);

  /// One "point" per element carrying the element means of `rule`: weight V_e = sum_q w_q det J_q,
  /// gradient (1/V_e) sum_q grad_X N_a w_q det J_q, value 1/n (the reference-cell mean of N_a on hex8
  /// and tet4), position the centroid.
  /// With a rule exact for det J grad_X N_a (degree >= 2 on trilinear hexes, any on linear tets) the
  /// gradients are the exact means (Flanagan & Belytschko 1981, IJNME 17:679, "uniform gradient"), so
  /// F = I + sum_a u_a (x) grad_X N_a at this point is the element's mean deformation gradient, and it
  /// equals the one-point rule at the element centre whenever the element is a parallelepiped.
  /// degree() is 1.
  static QuadratureData element_means(const QuadratureData& rule);

  int degree() const { return degree_; }
  int points_per_element() const { return points_; }
  int nodes_per_element() const { return nodes_; }
  std::size_t num_elements() const { return elements_; }
  /// w_q det J at point q of element e.
  double JxW(std::size_t e, int q) const { return jxw_[e * points_ + q]; }
  /// grad_X N_a at point q of element e.
  const Vec3& gradient(std::size_t e, int q, int a) const
  {
    return gradients_[(e * points_ + q) * nodes_ + a];
  }
  std::span<const Vec3> gradients(std::size_t e, int q) const
  {
    return {gradients_.data() + (e * points_ + q) * nodes_, static_cast<std::size_t>(nodes_)};
  }
  /// N_a at point q (the same on every element).
  double value(int q, int a) const { return values_[q * nodes_ + a]; }
  /// Reference position X of point q of element e.
  const Vec3& point(std::size_t e, int q) const { return points_X_[e * points_ + q]; }

 private:
  QuadratureData() = default;

  int degree_ = 2;
  int points_ = 0;
  int nodes_ = 0;
  std::size_t elements_ = 0;
  std::vector<double> jxw_;
  std::vector<Vec3> gradients_;
  std::vector<double> values_;
  std::vector<Vec3> points_X_;
};

/// This rank's share [begin, end) of `count` items split in contiguous blocks over `comm`
/// (the first count % size ranks get one more).
std::pair<std::size_t, std::size_t> local_range(std::size_t count, MPI_Comm comm);

/// Sums a replicated vector over the ranks of `comm` in place (MPI_Allreduce).
void sum_over_ranks(std::span<double> values, MPI_Comm comm);

} // namespace ibvalve::fe
