#include "fe/solid.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <limits>
#include <stdexcept>

#include <Eigen/LU>

#include "base/errors.hpp"

namespace ibvalve::fe {

namespace {

using Laws = std::vector<std::shared_ptr<const materials::StrainEnergy>>;

bool any_centre_laws(const std::vector<BodyPart>& parts)
{
  return std::any_of(parts.begin(), parts.end(), [](const BodyPart& p) { return !p.centre_laws.empty(); });
}

} // namespace

SolidModel::SolidModel(const Mesh& mesh, std::vector<BodyPart> parts, int quadrature_degree, MPI_Comm comm)
    : mesh_(mesh), parts_(std::move(parts)), quadrature_(mesh, quadrature_degree), comm_(comm),
      fibers_(mesh.num_elements())
{
  // The element means of the 2x2x2 Gauss rule, which integrates det J grad_X N_a of a trilinear hex
  // exactly (the cofactors of J are of degree <= 2 in each reference coordinate).
  if (any_centre_laws(parts_)) centre_ = QuadratureData::element_means(QuadratureData(mesh, 2));
  std::vector<std::pair<int, int>> items;
  std::vector<char> seen(mesh.num_elements(), 0);
  for (std::size_t p = 0; p < parts_.size(); ++p) {
    if (parts_[p].laws.empty() && parts_[p].centre_laws.empty())
      throw InputError("solid: body part '" + parts_[p].name + "' has no material law");
    for (int e : parts_[p].elements) {
      if (e < 0 || static_cast<std::size_t>(e) >= mesh.num_elements())
        throw std::invalid_argument("solid: body part '" + parts_[p].name +
                                    "' names an element that does not exist");
      if (seen[e]++) throw InputError(fmt::format("solid: element {} is in two body parts", e));
      items.emplace_back(static_cast<int>(p), e);
    }
  }
  const auto [begin, end] = local_range(items.size(), comm);
  local_items_.assign(items.begin() + begin, items.begin() + end);
}

void SolidModel::set_fibers(std::vector<materials::FiberFrame> fibers)
{
  const std::size_t per_element = mesh_.num_elements();
  const int points = quadrature_.points_per_element();
  const std::size_t per_point = per_element * points;
  if (fibers.size() != per_element && fibers.size() != per_point)
    throw std::invalid_argument("solid: fibers must be given per element or per quadrature point");
  fibers_per_point_ = fibers.size() == per_point && per_point != per_element;
  fibers_ = std::move(fibers);
  centre_fibers_.clear();
  if (fibers_per_point_ && centre_) {
    centre_fibers_.resize(per_element);
    for (std::size_t e = 0; e < per_element; ++e) {
      Vec3 f0 = Vec3::Zero(), s0 = Vec3::Zero();
      for (int q = 0; q < points; ++q) {
        f0 += quadrature_.JxW(e, q) * fibers_[e * points + q].f0;
        s0 += quadrature_.JxW(e, q) * fibers_[e * points + q].s0;
      }
      if (f0.norm() > 0) centre_fibers_[e].f0 = f0.normalized();
      if (s0.norm() > 0) centre_fibers_[e].s0 = s0.normalized();
    }
  }
}

const materials::FiberFrame& SolidModel::fibers(std::size_t e, int q) const
{
  return fibers_per_point_ ? fibers_[e * quadrature_.points_per_element() + q] : fibers_[e];
}

const materials::FiberFrame& SolidModel::centre_fibers(std::size_t e) const
{
  return centre_fibers_.empty() ? fibers_[fibers_per_point_ ? e * quadrature_.points_per_element() : e]
                                : centre_fibers_[e];
}

const materials::FiberFrame& SolidModel::frame(const QuadratureData& rule, std::size_t e, int q) const
{
  return &rule == &quadrature_ ? fibers(e, q) : centre_fibers(e);
}

Mat3 SolidModel::deformation_gradient(std::span<const double> u, std::size_t e, int q) const
{
  return deformation_gradient(quadrature_, u, e, q);
}

Mat3 SolidModel::deformation_gradient(const QuadratureData& rule, std::span<const double> u, std::size_t e,
                                      int q) const
{
  Mat3 F = Mat3::Identity();
  const auto element = mesh_.element(e);
  const auto gradients = rule.gradients(e, q);
  for (std::size_t a = 0; a < element.size(); ++a) {
    const Vec3 ua(u[3 * element[a]], u[3 * element[a] + 1], u[3 * element[a] + 2]);
    F.noalias() += ua * gradients[a].transpose();
  }
  return F;
}

template <int N>
void SolidModel::add_element_forces(const QuadratureData& rule, const Laws& laws, std::size_t e,
                                    const NodalMatrix<N>& U, NodalMatrix<N>& element_forces) const
{
  if (laws.empty()) return;
  const int n = mesh_.nodes_per_element();
  // Per point F = I + U G^T and f_e -= P G w det J with G the 3 x n matrix of grad_X N_a (stored
  // contiguously).
  for (int q = 0; q < rule.points_per_element(); ++q) {
    const Eigen::Map<const NodalMatrix<N>> G(rule.gradients(e, q).data()->data(), 3, n);
    const Mat3 F = Mat3::Identity() + U * G.transpose();
    Mat3 P = Mat3::Zero();
    for (const auto& law : laws) P += law->stress(F, frame(rule, e, q));
    element_forces.noalias() -= (rule.JxW(e, q) * P) * G;
  }
}

template <int N>
void SolidModel::add_forces(std::span<const double> u, std::span<double> forces, bool centre_laws) const
{
  const int n = mesh_.nodes_per_element();
  // Per element: gather the nodal displacements once (3 x n), sum both rules, scatter once.
  NodalMatrix<N> U(3, n), element_forces(3, n);
  for (const auto& [p, e] : local_items_) {
    const auto element = mesh_.element(e);
    for (int a = 0; a < n; ++a)
      for (int i = 0; i < 3; ++i) U(i, a) = u[3 * element[a] + i];
    element_forces.setZero();
    add_element_forces(quadrature_, parts_[p].laws, e, U, element_forces);
    if (centre_ && centre_laws) add_element_forces(*centre_, parts_[p].centre_laws, e, U, element_forces);
    for (int a = 0; a < n; ++a)
      for (int i = 0; i < 3; ++i) forces[3 * element[a] + i] += element_forces(i, a);
  }
}

void SolidModel::forces(std::span<const double> u, std::span<double> forces, bool centre_laws) const
{
  std::fill(forces.begin(), forces.end(), 0.0);
  // The trilinear hexahedron, the valve's element, with its 3 x 8 matrices sized at compile time (no
  // allocation, unrolled products); any other element with dynamic sizes.
  if (mesh_.nodes_per_element() == 8)
    add_forces<8>(u, forces, centre_laws);
  else
    add_forces<Eigen::Dynamic>(u, forces, centre_laws);
  sum_over_ranks(forces, comm_);
}

double SolidModel::element_energy(const QuadratureData& rule, const Laws& laws, std::span<const double> u,
                                  std::size_t e) const
{
  double total = 0.0;
  if (laws.empty()) return total;
  for (int q = 0; q < rule.points_per_element(); ++q) {
    const Mat3 F = deformation_gradient(rule, u, e, q);
    for (const auto& law : laws) total += law->energy(F, frame(rule, e, q)) * rule.JxW(e, q);
  }
  return total;
}

double SolidModel::energy(std::span<const double> u) const
{
  double total = 0.0;
  for (const auto& [p, e] : local_items_) {
    total += element_energy(quadrature_, parts_[p].laws, u, e);
    if (centre_) total += element_energy(*centre_, parts_[p].centre_laws, u, e);
  }
  sum_over_ranks(std::span<double>(&total, 1), comm_);
  return total;
}

void SolidModel::add_element_stiffness(const QuadratureData& rule, const Laws& laws,
                                       std::span<const double> u, std::size_t e,
                                       Eigen::MatrixXd& element_matrix) const
{
  if (laws.empty()) return;
  const int n = mesh_.nodes_per_element();
  std::vector<Eigen::Matrix<double, 9, 3>> M(n);
  for (int q = 0; q < rule.points_per_element(); ++q) {
    const Mat3 F = deformation_gradient(rule, u, e, q);
    materials::Tangent T = materials::Tangent::Zero();
    for (const auto& law : laws) T += law->tangent(F, frame(rule, e, q));
    T *= rule.JxW(e, q);
    const auto G = rule.gradients(e, q);
    // K_ab(i, k) = sum_jl T(i + 3j, k + 3l) G_a(j) G_b(l): first M_b(:, k) = sum_l T(:, k + 3l) G_b(l).
    for (int b = 0; b < n; ++b)
      for (int k = 0; k < 3; ++k)
        M[b].col(k) = T.col(k) * G[b][0] + T.col(k + 3) * G[b][1] + T.col(k + 6) * G[b][2];
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b)
        for (int i = 0; i < 3; ++i)
          for (int k = 0; k < 3; ++k)
            element_matrix(3 * a + i, 3 * b + k) +=
                M[b](i, k) * G[a][0] + M[b](i + 3, k) * G[a][1] + M[b](i + 6, k) * G[a][2];
  }
}

void SolidModel::add_stiffness(std::span<const double> u, const NodalSystem& system, Mat K) const
{
  const int n = mesh_.nodes_per_element();
  Eigen::MatrixXd element_matrix(3 * n, 3 * n);
  for (const auto& [p, e] : local_items_) {
    element_matrix.setZero();
    add_element_stiffness(quadrature_, parts_[p].laws, u, e, element_matrix);
    if (centre_) add_element_stiffness(*centre_, parts_[p].centre_laws, u, e, element_matrix);
    system.add_element_matrix(K, mesh_.element(e), element_matrix);
  }
}

Mat3 SolidModel::centre_cauchy_stress(int p, std::span<const double> u, std::size_t e) const
{
  if (!centre_ || parts_[p].centre_laws.empty()) return Mat3::Zero();
  const Mat3 F = deformation_gradient(*centre_, u, e, 0);
  Mat3 P = Mat3::Zero();
  for (const auto& law : parts_[p].centre_laws) P += law->stress(F, centre_fibers(e));
  return P * F.transpose() / F.determinant();
}

std::vector<Mat3> SolidModel::filtered_centre_stress(std::span<const double> u) const
{
  std::vector<Mat3> filtered(mesh_.num_elements(), Mat3::Zero());
  if (!centre_) return filtered;
  // Per part and node: the volume-weighted sums of the six stress components and of the volumes.
  constexpr int stride = 7;
  const std::size_t nodes = mesh_.num_nodes();
  std::vector<double> sums(parts_.size() * nodes * stride, 0.0);
  for (const auto& [p, e] : local_items_) {
    const Mat3 s = centre_cauchy_stress(p, u, e);
    const double volume = centre_->JxW(e, 0);
    const double components[stride] = {s(0, 0), s(1, 1), s(2, 2), s(0, 1), s(0, 2), s(1, 2), 1.0};
    for (const int a : mesh_.element(e))
      for (int k = 0; k < stride; ++k) sums[(p * nodes + a) * stride + k] += volume * components[k];
  }
  sum_over_ranks(sums, comm_);
  for (const auto& [p, e] : local_items_) {
    const auto element_nodes = mesh_.element(e);
    double mean[stride - 1] = {};
    for (const int a : element_nodes) {
      const double* node = &sums[(p * nodes + a) * stride];
      for (int k = 0; k + 1 < stride; ++k) mean[k] += node[k] / node[stride - 1];
    }
    for (double& m : mean) m /= static_cast<double>(element_nodes.size());
    filtered[e] << mean[0], mean[3], mean[4], mean[3], mean[1], mean[5], mean[4], mean[5], mean[2];
  }
  return filtered;
}

ElementFields SolidModel::element_fields(std::span<const double> u) const
{
  const std::size_t count = mesh_.num_elements();
  std::vector<double> packed(count * 6, 0.0); // J, strain, stress, f (3)
  const int points = quadrature_.points_per_element();
  const std::vector<Mat3> centre_stress = filtered_centre_stress(u);
  for (const auto& [p, e] : local_items_) {
    double volume = 0.0;
    double* out = &packed[6 * e];
    const Mat3& centre_sigma = centre_stress[e];
    for (int q = 0; q < points; ++q) {
      const double w = quadrature_.JxW(e, q);
      const Mat3 F = deformation_gradient(u, e, q);
      const double J = F.determinant();
      volume += w;
      out[0] += w * J;
      const Vec3& f0 = fibers(e, q).f0;
      if (f0.squaredNorm() == 0.0) continue;
      Mat3 P = Mat3::Zero();
      for (const auto& law : parts_[p].laws) P += law->stress(F, fibers(e, q));
      const Mat3 E = 0.5 * (F.transpose() * F - Mat3::Identity());
      const Mat3 sigma = P * F.transpose() / J + centre_sigma;
      const Vec3 f = (F * f0).normalized();
      out[1] += w * f0.dot(E * f0);
      out[2] += w * f.dot(sigma * f);
      for (int i = 0; i < 3; ++i) out[3 + i] += w * f[i];
    }
    for (int k = 0; k < 6; ++k) out[k] /= volume;
  }
  sum_over_ranks(packed, comm_);
  ElementFields fields;
  fields.J.resize(count);
  fields.fiber_strain.resize(count);
  fields.fiber_stress.resize(count);
  fields.fiber_direction.resize(count);
  for (std::size_t e = 0; e < count; ++e) {
    fields.J[e] = packed[6 * e];
    fields.fiber_strain[e] = packed[6 * e + 1];
    fields.fiber_stress[e] = packed[6 * e + 2];
    const Vec3 f(packed[6 * e + 3], packed[6 * e + 4], packed[6 * e + 5]);
    fields.fiber_direction[e] = f.norm() > 0 ? Vec3(f.normalized()) : Vec3::Zero();
  }
  return fields;
}

PointFields SolidModel::point_fields(std::span<const double> u) const
{
  const int points = quadrature_.points_per_element();
  const std::size_t count = mesh_.num_elements() * points;
  std::vector<double> packed(3 * count, 0.0);
  const std::vector<Mat3> centre_stress = filtered_centre_stress(u);
  for (const auto& [p, e] : local_items_) {
    const Mat3& centre_sigma = centre_stress[e];
    for (int q = 0; q < points; ++q) {
      const std::size_t k = e * points + q;
      const Mat3 F = deformation_gradient(u, e, q);
      const double J = F.determinant();
      packed[k] = J;
      const Vec3& f0 = fibers(e, q).f0;
      if (f0.squaredNorm() == 0.0) continue;
      Mat3 P = Mat3::Zero();
      for (const auto& law : parts_[p].laws) P += law->stress(F, fibers(e, q));
      const Vec3 f = (F * f0).normalized();
      packed[count + k] = 0.5 * ((F * f0).squaredNorm() - f0.squaredNorm());     // f0 . E f0
      packed[2 * count + k] = f.dot((P * F.transpose() / J + centre_sigma) * f); // f . sigma f
    }
  }
  sum_over_ranks(packed, comm_);
  PointFields fields;
  fields.J.assign(packed.begin(), packed.begin() + count);
  fields.fiber_strain.assign(packed.begin() + count, packed.begin() + 2 * count);
  fields.fiber_stress.assign(packed.begin() + 2 * count, packed.end());
  return fields;
}

SmallestJacobian SolidModel::smallest_point_jacobian(std::span<const double> u) const
{
  // MPI_MINLOC over (J, element) pairs; a rank without elements offers (+inf, INT_MAX).
  struct {
    double J;
    int element;
  } local{std::numeric_limits<double>::infinity(), -1}, global{};
  for (const auto& [p, e] : local_items_)
    for (int q = 0; q < quadrature_.points_per_element(); ++q) {
      const double J = deformation_gradient(u, e, q).determinant();
      if (J < local.J) local = {J, e};
    }
  if (local.element < 0) local.element = std::numeric_limits<int>::max();
  MPI_Allreduce(&local, &global, 1, MPI_DOUBLE_INT, MPI_MINLOC, comm_);
  if (global.element == std::numeric_limits<int>::max()) return {};
  return {global.J, global.element};
}

} // namespace ibvalve::fe
