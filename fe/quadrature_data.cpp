#include "fe/quadrature_data.hpp"

#include <Eigen/LU>
#include <fmt/format.h>

#include "base/errors.hpp"

namespace ibvalve::fe {

QuadratureData::QuadratureData(const Mesh& mesh, int degree)
    : degree_(degree), nodes_(mesh.nodes_per_element()), elements_(mesh.num_elements())
{
  const ElementType& type = mesh.type();
  const QuadratureRule rule = type.quadrature(degree);
  points_ = static_cast<int>(rule.size());
  values_.resize(points_ * nodes_);
  std::vector<std::vector<Vec3>> reference_gradients(points_, std::vector<Vec3>(nodes_));
  for (int q = 0; q < points_; ++q) {
    type.values(rule.points[q], std::span<double>(values_.data() + q * nodes_, nodes_));
    type.gradients(rule.points[q], reference_gradients[q]);
  }
  jxw_.resize(elements_ * points_);
  gradients_.resize(elements_ * points_ * nodes_);
  points_X_.resize(elements_ * points_);
  for (std::size_t e = 0; e < elements_; ++e) {
    const auto element = mesh.element(e);
    for (int q = 0; q < points_; ++q) {
      Eigen::Matrix3d jacobian = Eigen::Matrix3d::Zero(); // dX/dxi
      Vec3 X = Vec3::Zero();
      for (int a = 0; a < nodes_; ++a) {
        jacobian += mesh.nodes()[element[a]] * reference_gradients[q][a].transpose();
        X += values_[q * nodes_ + a] * mesh.nodes()[element[a]];
      }
      const double det = jacobian.determinant();
      if (!(det > 0))
        throw InputError(fmt::format("mesh: element {} is inverted or degenerate (det J = {:g})", e, det));
      const Eigen::Matrix3d inverse_transpose = jacobian.inverse().transpose();
      jxw_[e * points_ + q] = det * rule.weights[q];
      points_X_[e * points_ + q] = X;
      for (int a = 0; a < nodes_; ++a)
        gradients_[(e * points_ + q) * nodes_ + a] = inverse_transpose * reference_gradients[q][a];
    }
  }
}

QuadratureData QuadratureData::element_means(const QuadratureData& rule)
{
  QuadratureData mean;
  mean.degree_ = 1;
  mean.points_ = 1;
  mean.nodes_ = rule.nodes_;
  mean.elements_ = rule.elements_;
  const int n = rule.nodes_;
  // Mean of N_a over the reference cell: 1/n for hex8 and tet4 (partition of unity, equivalent nodes).
  mean.values_.assign(n, 1.0 / n);
  mean.jxw_.assign(mean.elements_, 0.0);
  mean.gradients_.assign(mean.elements_ * n, Vec3::Zero());
  mean.points_X_.assign(mean.elements_, Vec3::Zero());
  for (std::size_t e = 0; e < mean.elements_; ++e) {
    double volume = 0.0;
    for (int q = 0; q < rule.points_; ++q) {
      const double w = rule.JxW(e, q);
      volume += w;
      mean.points_X_[e] += w * rule.point(e, q);
      for (int a = 0; a < n; ++a) mean.gradients_[e * n + a] += w * rule.gradient(e, q, a);
    }
    mean.jxw_[e] = volume;
    mean.points_X_[e] /= volume;
    for (int a = 0; a < n; ++a) mean.gradients_[e * n + a] /= volume;
  }
  return mean;
}

std::pair<std::size_t, std::size_t> local_range(std::size_t count, MPI_Comm comm)
{
  int size = 1, rank = 0;
  MPI_Comm_size(comm, &size);
  MPI_Comm_rank(comm, &rank);
  const std::size_t base = count / size, extra = count % size;
  const std::size_t r = static_cast<std::size_t>(rank);
  const std::size_t begin = r * base + std::min(r, extra);
  return {begin, begin + base + (r < extra ? 1 : 0)};
}

void sum_over_ranks(std::span<double> values, MPI_Comm comm)
{
  int size = 1;
  MPI_Comm_size(comm, &size);
  if (size == 1 || values.empty()) return;
  MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()), MPI_DOUBLE, MPI_SUM, comm);
}

} // namespace ibvalve::fe
