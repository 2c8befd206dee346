#pragma once
// External nodal loads in weak form: a body force per unit reference volume, int b(X) N_a dX, and a
// dead (reference-configuration) traction on a surface group, int_{group} T(X) N_a dA. Both are
// replicated over the ranks (split over elements/faces, summed with MPI_Allreduce).
#include <functional>
#include <string>
#include <vector>

#include <mpi.h>

#include "fe/quadrature_data.hpp"

namespace ibvalve::fe {

std::vector<double> body_force_load(const Mesh& mesh, const QuadratureData& quadrature,
                                    const std::function<Vec3(const Vec3& X)>& body_force, MPI_Comm comm);

/// Dead traction on the faces of surface group `group`, integrated with a rule of degree `degree`.
std::vector<double> surface_traction_load(const Mesh& mesh, const std::string& group,
                                          const std::function<Vec3(const Vec3& X)>& traction, int degree,
                                          MPI_Comm comm);

/// Reference area of a surface group.
double surface_area(const Mesh& mesh, const std::string& group);

} // namespace ibvalve::fe
