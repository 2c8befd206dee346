#include "fe/loads.hpp"

#include "base/errors.hpp"

namespace ibvalve::fe {

std::vector<double> body_force_load(const Mesh& mesh, const QuadratureData& quadrature,
                                    const std::function<Vec3(const Vec3&)>& body_force, MPI_Comm comm)
{
  std::vector<double> load(3 * mesh.num_nodes(), 0.0);
  const auto [begin, end] = local_range(mesh.num_elements(), comm);
  for (std::size_t e = begin; e < end; ++e) {
    const auto element = mesh.element(e);
    for (int q = 0; q < quadrature.points_per_element(); ++q) {
      const Vec3 b = body_force(quadrature.point(e, q)) * quadrature.JxW(e, q);
      for (std::size_t a = 0; a < element.size(); ++a)
        for (int i = 0; i < 3; ++i)
          load[3 * element[a] + i] += quadrature.value(q, static_cast<int>(a)) * b[i];
    }
  }
  sum_over_ranks(load, comm);
  return load;
}

namespace {

// Calls visit(face nodes, point X, N values, weight * area Jacobian) at every quadrature point of the
// faces [begin, end) of a surface group.
template <class Visit>
void for_face_points(const Mesh& mesh, const PhysicalGroup& group, int degree, std::size_t begin,
                     std::size_t end, Visit visit)
{
  const ElementType& type = element_type(group.cell_shape);
  const QuadratureRule rule = type.quadrature(degree);
  const int k = type.num_nodes();
  std::vector<double> N(k);
  std::vector<Vec3> dN(k);
  for (std::size_t c = begin; c < end; ++c) {
    const std::span<const int> face(group.cells.data() + c * k, k);
    for (std::size_t q = 0; q < rule.size(); ++q) {
      type.values(rule.points[q], N);
      type.gradients(rule.points[q], dN);
      Vec3 X = Vec3::Zero(), t1 = Vec3::Zero(), t2 = Vec3::Zero();
      for (int a = 0; a < k; ++a) {
        const Vec3& x = mesh.nodes()[face[a]];
        X += N[a] * x;
        t1 += dN[a][0] * x;
        t2 += dN[a][1] * x;
      }
      visit(face, X, N, rule.weights[q] * t1.cross(t2).norm());
    }
  }
}

const PhysicalGroup& surface_group(const Mesh& mesh, const std::string& name)
{
  const PhysicalGroup& group = mesh.group(name);
  if (group.dimension != 2) throw InputError("mesh: physical group '" + name + "' is not a surface");
  return group;
}

} // namespace

std::vector<double> surface_traction_load(const Mesh& mesh, const std::string& name,
                                          const std::function<Vec3(const Vec3&)>& traction, int degree,
                                          MPI_Comm comm)
{
  const PhysicalGroup& group = surface_group(mesh, name);
  std::vector<double> load(3 * mesh.num_nodes(), 0.0);
  const std::size_t faces = group.cells.size() / nodes_per_cell(group.cell_shape);
  const auto [begin, end] = local_range(faces, comm);
  for_face_points(mesh, group, degree, begin, end,
                  [&](std::span<const int> face, const Vec3& X, const std::vector<double>& N, double w) {
                    const Vec3 t = traction(X) * w;
                    for (std::size_t a = 0; a < face.size(); ++a)
                      for (int i = 0; i < 3; ++i) load[3 * face[a] + i] += N[a] * t[i];
                  });
  sum_over_ranks(load, comm);
  return load;
}

double surface_area(const Mesh& mesh, const std::string& name)
{
  const PhysicalGroup& group = surface_group(mesh, name);
  double area = 0.0;
  for_face_points(
      mesh, group, 2, 0, group.cells.size() / nodes_per_cell(group.cell_shape),
      [&](std::span<const int>, const Vec3&, const std::vector<double>&, double w) { area += w; });
  return area;
}

} // namespace ibvalve::fe
