#pragma once
// The hyperelastic solid on a finite-element mesh: body parts (each a set of elements with its
// strain-energy law(s) — e.g. W1 plus a volumetric penalty — summed), fiber frames per element or
// per quadrature point, and the weak-form quantities at a displacement u (nodal, interlaced x y z):
//   nodal forces   F_a = - sum_q P(F_q) grad_X N_a(X_q) w_q det J_q   (DESIGN.md: -int P : grad_X N_a dX)
//   stiffness      K_ab = sum_q grad_X N_a . (dP/dF) . grad_X N_b w_q det J_q   (= -dF_a/du_b)
//   energy         sum_q W(F_q) w_q det J_q
// with F_q = I + sum_a u_a (x) grad_X N_a.
//
// Parallel: the mesh is replicated; the (part, element) pairs are split in contiguous blocks over the
// ranks, each rank loops over its block, and nodal vectors are summed with MPI_Allreduce, so every
// rank ends with the whole force vector (what IB spreading needs). Matrices go to PETSc, which moves
// off-rank rows to their owners.
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <petscmat.h>

#include "fe/nodal_system.hpp"
#include "fe/quadrature_data.hpp"
#include "materials/strain_energy.hpp"

namespace ibvalve::fe {

using Mat3 = Eigen::Matrix3d;

struct BodyPart {
  std::string name;
  std::vector<int> elements;
  /// Laws summed at every point of the part (a tissue law and a volumetric penalty, for instance).
  std::vector<std::shared_ptr<const materials::StrainEnergy>> laws;
};

/// Per-element averages of the quantities one looks at in ParaView (REFERENCE.md): J = det F, the
/// fiber strain f0 . E f0 with E = (C - I)/2, the fiber stress f . sigma f with f = F f0 / |F f0| and
/// sigma = P F^T / J, the current fiber direction f; averaged over the element's quadrature points
/// with their weights. Fiber quantities are zero where f0 is zero.
struct ElementFields {
  std::vector<double> J;
  std::vector<double> fiber_strain;
  std::vector<double> fiber_stress;
  std::vector<Vec3> fiber_direction; ///< current f (unit)
};

/// The same quantities at every quadrature point (index e * points_per_element + q), for L2
/// projection to nodes.
struct PointFields {
  std::vector<double> J;
  std::vector<double> fiber_strain;
  std::vector<double> fiber_stress;
};

class SolidModel {
 public:
  /// Keeps a reference to `mesh`, which must outlive the model.
  SolidModel(const Mesh& mesh, std::vector<BodyPart> parts, int quadrature_degree, MPI_Comm comm);

  const Mesh& mesh() const { return mesh_; }
  const QuadratureData& quadrature() const { return quadrature_; }
  const std::vector<BodyPart>& parts() const { return parts_; }
  MPI_Comm comm() const { return comm_; }
  std::size_t num_dofs() const { return 3 * mesh_.num_nodes(); }

  /// Fiber frames, one per element (size num_elements) or one per quadrature point
  /// (size num_elements x points_per_element, element-major).
  void set_fibers(std::vector<materials::FiberFrame> fibers);
  const materials::FiberFrame& fibers(std::size_t e, int q) const;

  /// F at point q of element e for the replicated displacement u.
  Mat3 deformation_gradient(std::span<const double> u, std::size_t e, int q) const;

  /// Nodal forces (replicated on every rank, summed over them). `forces` is overwritten.
  void forces(std::span<const double> u, std::span<double> forces) const;
  /// Total strain energy (the same on every rank).
  double energy(std::span<const double> u) const;
  /// Adds this rank's element stiffness matrices to `K` (layout of `system`, 3 dofs per node); the
  /// caller assembles.
  void add_stiffness(std::span<const double> u, const NodalSystem& system, Mat K) const;
  /// The fields of ElementFields (replicated).
  ElementFields element_fields(std::span<const double> u) const;
  /// J, fiber strain and fiber stress at every quadrature point (replicated).
  PointFields point_fields(std::span<const double> u) const;

  /// The (part, element) pairs this rank works on.
  std::span<const std::pair<int, int>> local_items() const { return local_items_; }

 private:
  const Mesh& mesh_;
  std::vector<BodyPart> parts_;
  QuadratureData quadrature_;
  MPI_Comm comm_;
  std::vector<materials::FiberFrame> fibers_;
  bool fibers_per_point_ = false;
  std::vector<std::pair<int, int>> local_items_;
};

} // namespace ibvalve::fe
