#include "fibers/laplace.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <sstream>

#include <petscksp.h>

#include "base/errors.hpp"
#include "fe/nodal_system.hpp"
#include "io/petsc_check.hpp"

namespace ibvalve::fibers {

std::vector<double> solve_laplace(const fe::Mesh& mesh, const std::vector<DirichletSet>& conditions,
                                  MPI_Comm comm, const LaplaceOptions& options)
{
  if (conditions.empty()) throw InputError("fibers: a Laplace problem needs Dirichlet data");
  for (const auto& set : conditions)
    if (set.nodes.empty()) throw InputError("fibers: a Dirichlet set selects no node");

  const fe::QuadratureData quadrature(mesh, 2);
  const fe::NodalSystem system(mesh, 1, comm);
  const petsc::OwnedMat K = system.create_matrix();
  const int n = mesh.nodes_per_element();
  Eigen::MatrixXd element_matrix(n, n);
  const auto [begin, end] = fe::local_range(mesh.num_elements(), comm);
  for (std::size_t e = begin; e < end; ++e) {
    element_matrix.setZero();
    for (int q = 0; q < quadrature.points_per_element(); ++q)
      for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b)
          element_matrix(a, b) +=
              quadrature.gradient(e, q, a).dot(quadrature.gradient(e, q, b)) * quadrature.JxW(e, q);
    system.add_element_matrix(K, mesh.element(e), element_matrix);
  }
  PETSC_CHECK(MatAssemblyBegin(K, MAT_FINAL_ASSEMBLY));
  PETSC_CHECK(MatAssemblyEnd(K, MAT_FINAL_ASSEMBLY));

  // Known values in x; MatZeroRowsColumns moves their columns into b and puts 1 on the diagonal.
  std::vector<double> known(mesh.num_nodes(), 0.0);
  std::vector<PetscInt> rows;
  for (const auto& set : conditions)
    for (int node : set.nodes) {
      known[node] = set.value;
      rows.push_back(node);
    }
  std::sort(rows.begin(), rows.end());
  rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  const petsc::OwnedVec x = system.create_vector(), b = system.create_vector();
  system.scatter(known, x);
  PETSC_CHECK(VecSet(b, 0.0));
  fe::zero_rows_columns(K, rows, 1.0, x, b);

  petsc::OwnedKSP ksp;
  PETSC_CHECK(KSPCreate(comm, ksp.out()));
  PETSC_CHECK(KSPSetOptionsPrefix(ksp, options.prefix.c_str()));
  PETSC_CHECK(KSPSetOperators(ksp, K, K));
  PETSC_CHECK(KSPSetType(ksp, KSPCG));
  PC pc;
  PETSC_CHECK(KSPGetPC(ksp, &pc));
#if defined(PETSC_HAVE_HYPRE)
  PETSC_CHECK(PCSetType(pc, PCHYPRE));
#else
  PETSC_CHECK(PCSetType(pc, PCGAMG));
#endif
  PETSC_CHECK(KSPSetTolerances(ksp, options.relative_tolerance, 1e-300, PETSC_DEFAULT, 2000));
  PETSC_CHECK(KSPSetFromOptions(ksp));
  PETSC_CHECK(KSPSolve(ksp, b, x));
  KSPConvergedReason reason;
  PETSC_CHECK(KSPGetConvergedReason(ksp, &reason));
  std::vector<double> u = system.gather(x);
  if (reason < 0)
    throw RunError(std::string("fibers: the Laplace solve did not converge (") + KSPConvergedReasons[reason] +
                   ")");
  return u;
}

namespace {

Vec3 gradient_at(const fe::Mesh& mesh, const fe::QuadratureData& quadrature, std::span<const double> u,
                 std::size_t e, int q)
{
  Vec3 g = Vec3::Zero();
  const auto element = mesh.element(e);
  for (std::size_t a = 0; a < element.size(); ++a)
    g += u[element[a]] * quadrature.gradient(e, q, static_cast<int>(a));
  return g;
}

Vec3 unit_or_zero(const Vec3& v)
{
  const double norm = v.norm();
  return norm > 0 ? Vec3(v / norm) : Vec3::Zero();
}

} // namespace

std::vector<Vec3> directions_at_points(const fe::Mesh& mesh, const fe::QuadratureData& quadrature,
                                       std::span<const double> u)
{
  const int points = quadrature.points_per_element();
  std::vector<Vec3> directions(mesh.num_elements() * points);
  for (std::size_t e = 0; e < mesh.num_elements(); ++e)
    for (int q = 0; q < points; ++q)
      directions[e * points + q] = unit_or_zero(gradient_at(mesh, quadrature, u, e, q));
  return directions;
}

std::vector<Vec3> directions_per_element(const fe::Mesh& mesh, const fe::QuadratureData& quadrature,
                                         std::span<const double> u)
{
  std::vector<Vec3> directions(mesh.num_elements());
  for (std::size_t e = 0; e < mesh.num_elements(); ++e) {
    Vec3 sum = Vec3::Zero();
    for (int q = 0; q < quadrature.points_per_element(); ++q)
      sum += gradient_at(mesh, quadrature, u, e, q) * quadrature.JxW(e, q);
    directions[e] = unit_or_zero(sum);
  }
  return directions;
}

std::vector<int> nodes_of_group(const fe::Mesh& mesh, const std::string& group)
{
  return mesh.group(group).nodes;
}

int nearest_node(const fe::Mesh& mesh, const Vec3& point)
{
  int best = -1;
  double distance = std::numeric_limits<double>::infinity();
  for (std::size_t n = 0; n < mesh.num_nodes(); ++n) {
    const double d = (mesh.nodes()[n] - point).squaredNorm();
    if (d < distance) {
      distance = d;
      best = static_cast<int>(n);
    }
  }
  return best;
}

std::vector<int> boundary_nodes_on_plane(const fe::Mesh& mesh, const Vec3& point, const Vec3& normal,
                                         double tolerance)
{
  const Vec3 unit = normal.normalized();
  std::vector<char> on_boundary(mesh.num_nodes(), 0);
  for (const auto& face : mesh.boundary_faces())
    for (int n : face) on_boundary[n] = 1;
  std::vector<int> nodes;
  for (std::size_t n = 0; n < mesh.num_nodes(); ++n)
    if (on_boundary[n] && std::abs((mesh.nodes()[n] - point).dot(unit)) <= tolerance)
      nodes.push_back(static_cast<int>(n));
  return nodes;
}

namespace {

std::vector<double> parse_numbers(const std::string& text, std::size_t count, const std::string& selector)
{
  std::vector<double> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    try {
      std::size_t used = 0;
      values.push_back(std::stod(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw InputError("fibers: selector '" + selector + "': '" + item + "' is not a number");
    }
  }
  if (values.size() != count)
    throw InputError(fmt::format("fibers: selector '{}' needs {} numbers", selector, count));
  return values;
}

} // namespace

std::vector<int> select_nodes(const fe::Mesh& mesh, const std::string& selector)
{
  std::vector<int> nodes;
  if (selector.rfind("point:", 0) == 0) {
    const auto v = parse_numbers(selector.substr(6), 3, selector);
    nodes.push_back(nearest_node(mesh, Vec3(v[0], v[1], v[2])));
  } else if (selector.rfind("plane:", 0) == 0) {
    const auto v = parse_numbers(selector.substr(6), 6, selector);
    const Vec3 normal(v[3], v[4], v[5]);
    if (normal.norm() == 0) throw InputError("fibers: selector '" + selector + "' has a zero normal");
    nodes =
        boundary_nodes_on_plane(mesh, Vec3(v[0], v[1], v[2]), normal, 1e-3 * mesh.edge_length_range().first);
  } else {
    nodes = nodes_of_group(mesh, selector);
  }
  if (nodes.empty()) throw InputError("fibers: selector '" + selector + "' matches no node");
  return nodes;
}

} // namespace ibvalve::fibers
