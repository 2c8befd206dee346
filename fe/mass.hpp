#pragma once
// Mass matrices and L2 projection of quadrature-point data onto the nodal (Lagrange) space.
//   consistent mass  M_ab = int N_a N_b dX        lumped mass  m_a = sum_b M_ab = int N_a dX
// (row-sum lumping; positive for linear tetrahedra and trilinear hexahedra). The L2 projection of
// g(X) is the nodal field v with M v = b, b_a = int N_a g dX (consistent; exact for fields in the FE
// space, hence for linear fields) or v_a = b_a / m_a (lumped; local, first order).
#include <span>
#include <string>
#include <vector>

#include <petscksp.h>

#include "fe/nodal_system.hpp"
#include "fe/quadrature_data.hpp"

namespace ibvalve::fe {

/// Consistent mass matrix (scalar, one row per node), assembled over `system`'s layout; each rank
/// integrates its element range. The caller owns the Mat.
petsc::OwnedMat consistent_mass_matrix(const Mesh& mesh, const QuadratureData& quadrature,
                                       const NodalSystem& system);

/// Lumped (row-sum) mass, replicated.
std::vector<double> lumped_mass(const Mesh& mesh, const QuadratureData& quadrature, MPI_Comm comm);

enum class MassKind { consistent, lumped };

class L2Projection {
 public:
  /// The consistent solve uses a PETSc KSP with options prefix `prefix` (default CG + Jacobi,
  /// relative tolerance 1e-13).
  L2Projection(const Mesh& mesh, const QuadratureData& quadrature, MassKind kind, MPI_Comm comm,
               const std::string& prefix = "l2_");
  L2Projection(const L2Projection&) = delete;
  L2Projection& operator=(const L2Projection&) = delete;

  /// Projects `components`-valued data given at every quadrature point (index
  /// ((e * points + q) * components + c)) to nodal values (index n * components + c), replicated.
  std::vector<double> project(std::span<const double> point_values, int components) const;
  /// Projects a function of the reference position.
  std::vector<double> project(const std::function<double(const Vec3&)>& g) const;

 private:
  const Mesh& mesh_;
  const QuadratureData& quadrature_;
  MassKind kind_;
  MPI_Comm comm_;
  NodalSystem system_;
  std::vector<double> lumped_;
  petsc::OwnedMat mass_;
  petsc::OwnedKSP ksp_;
};

} // namespace ibvalve::fe
