#include "fe/mass.hpp"

#include "io/petsc_check.hpp"

namespace ibvalve::fe {

petsc::OwnedMat consistent_mass_matrix(const Mesh& mesh, const QuadratureData& quadrature,
                                       const NodalSystem& system)
{
  petsc::OwnedMat M = system.create_matrix();
  const int n = mesh.nodes_per_element();
  Eigen::MatrixXd element_matrix(n, n);
  const auto [begin, end] = local_range(mesh.num_elements(), system.comm());
  for (std::size_t e = begin; e < end; ++e) {
    element_matrix.setZero();
    for (int q = 0; q < quadrature.points_per_element(); ++q)
      for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b)
          element_matrix(a, b) += quadrature.value(q, a) * quadrature.value(q, b) * quadrature.JxW(e, q);
    system.add_element_matrix(M, mesh.element(e), element_matrix);
  }
  PETSC_CHECK(MatAssemblyBegin(M, MAT_FINAL_ASSEMBLY));
  PETSC_CHECK(MatAssemblyEnd(M, MAT_FINAL_ASSEMBLY));
  return M;
}

std::vector<double> lumped_mass(const Mesh& mesh, const QuadratureData& quadrature, MPI_Comm comm)
{
  std::vector<double> mass(mesh.num_nodes(), 0.0);
  const auto [begin, end] = local_range(mesh.num_elements(), comm);
  for (std::size_t e = begin; e < end; ++e) {
    const auto element = mesh.element(e);
    for (int q = 0; q < quadrature.points_per_element(); ++q)
      for (std::size_t a = 0; a < element.size(); ++a)
        mass[element[a]] += quadrature.value(q, static_cast<int>(a)) * quadrature.JxW(e, q);
  }
  sum_over_ranks(mass, comm);
  return mass;
}

L2Projection::L2Projection(const Mesh& mesh, const QuadratureData& quadrature, MassKind kind, MPI_Comm comm,
                           const std::string& prefix)
    : mesh_(mesh), quadrature_(quadrature), kind_(kind), comm_(comm), system_(mesh, 1, comm)
{
  lumped_ = lumped_mass(mesh, quadrature, comm);
  if (kind_ == MassKind::lumped) return;
  mass_ = consistent_mass_matrix(mesh, quadrature, system_);
  PETSC_CHECK(KSPCreate(comm, ksp_.out()));
  PETSC_CHECK(KSPSetOptionsPrefix(ksp_, prefix.c_str()));
  PETSC_CHECK(KSPSetOperators(ksp_, mass_, mass_));
  PETSC_CHECK(KSPSetType(ksp_, KSPCG));
  PC pc;
  PETSC_CHECK(KSPGetPC(ksp_, &pc));
  PETSC_CHECK(PCSetType(pc, PCJACOBI));
  PETSC_CHECK(KSPSetTolerances(ksp_, 1e-13, 1e-300, PETSC_DEFAULT, 1000));
  PETSC_CHECK(KSPSetFromOptions(ksp_));
}

std::vector<double> L2Projection::project(std::span<const double> point_values, int components) const
{
  const std::size_t nodes = mesh_.num_nodes();
  const int points = quadrature_.points_per_element();
  std::vector<double> rhs(nodes * components, 0.0);
  const auto [begin, end] = local_range(mesh_.num_elements(), comm_);
  for (std::size_t e = begin; e < end; ++e) {
    const auto element = mesh_.element(e);
    for (int q = 0; q < points; ++q)
      for (std::size_t a = 0; a < element.size(); ++a) {
        const double w = quadrature_.value(q, static_cast<int>(a)) * quadrature_.JxW(e, q);
        for (int c = 0; c < components; ++c)
          rhs[element[a] * components + c] += w * point_values[(e * points + q) * components + c];
      }
  }
  sum_over_ranks(rhs, comm_);
  std::vector<double> result(nodes * components);
  if (kind_ == MassKind::lumped) {
    for (std::size_t n = 0; n < nodes; ++n)
      for (int c = 0; c < components; ++c) result[n * components + c] = rhs[n * components + c] / lumped_[n];
    return result;
  }
  const petsc::OwnedVec b = system_.create_vector(), x = system_.create_vector();
  std::vector<double> one(nodes);
  for (int c = 0; c < components; ++c) {
    for (std::size_t n = 0; n < nodes; ++n) one[n] = rhs[n * components + c];
    system_.scatter(one, b);
    // The lumped solution is a good first guess.
    for (std::size_t n = 0; n < nodes; ++n) one[n] /= lumped_[n];
    system_.scatter(one, x);
    PETSC_CHECK(KSPSetInitialGuessNonzero(ksp_, PETSC_TRUE));
    PETSC_CHECK(KSPSolve(ksp_, b, x));
    const std::vector<double> solved = system_.gather(x);
    for (std::size_t n = 0; n < nodes; ++n) result[n * components + c] = solved[n];
  }
  return result;
}

std::vector<double> L2Projection::project(const std::function<double(const Vec3&)>& g) const
{
  const int points = quadrature_.points_per_element();
  std::vector<double> values(mesh_.num_elements() * points);
  for (std::size_t e = 0; e < mesh_.num_elements(); ++e)
    for (int q = 0; q < points; ++q) values[e * points + q] = g(quadrature_.point(e, q));
  return project(values, 1);
}

} // namespace ibvalve::fe
