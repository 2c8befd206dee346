#pragma once
// The hyperelastic solid on a finite-element mesh: body parts (each a set of elements with its
// strain-energy law(s) — e.g. W1 plus a volumetric penalty — summed), fiber frames per element or
// per quadrature point, and the weak-form quantities at a displacement u (nodal, interlaced x y z):
//   nodal forces   F_a = - sum_q P(F_q) grad_X N_a(X_q) w_q det J_q   (-int P : grad_X N_a dX)
//   stiffness      K_ab = sum_q grad_X N_a . (dP/dF) . grad_X N_b w_q det J_q   (= -dF_a/du_b)
//   energy         sum_q W(F_q) w_q det J_q
// with F_q = I + sum_a u_a (x) grad_X N_a (the weak form of the IB force: docs/reference.md, "Structure
// and coupling").
//
// Selective reduced integration (SRI): a part may name `centre_laws`, integrated with one point per
// element instead of the full rule: the law is evaluated at the element's mean deformation gradient
// F_e = (1/V_e) int F dX = I + sum_a u_a (x) gbar_a, gbar_a = (1/V_e) int grad_X N_a dX, with weight
// V_e. On a parallelepiped this is exactly the one-point Gauss rule at the element centre; on a
// distorted hex the exact means (the "uniform gradient" of Flanagan & Belytschko 1981, IJNME 17:679)
// keep the patch test, which the plain centre point fails. Each quantity above is then the full-rule
// sum of `laws` plus this one-point sum of `centre_laws`. With the volumetric penalty U(J) as the centre
// law this is the standard cure for volumetric locking of trilinear hexes in nearly incompressible
// bending (Malkus & Hughes 1978, CMAME 15:63, the equivalence with mixed methods; Hughes 1980, IJNME
// 15:1413, the generalisation to anisotropic and nonlinear media with the element-mean dilatation):
// one volumetric constraint per element instead of eight, while the law, fully integrated, keeps the
// element free of hourglass modes. Forces, energy and stiffness use the same split, so the forces stay
// minus the energy gradient and the stiffness their exact derivative.
//
// Parallel: the mesh is replicated; the (part, element) pairs are split in contiguous blocks over the
// ranks, each rank loops over its block, and nodal vectors are summed with MPI_Allreduce, so every
// rank ends with the whole force vector (what IB spreading needs). Matrices go to PETSc, which moves
// off-rank rows to their owners.
#include <memory>
#include <optional>
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
  /// Laws summed at every point of the full rule (a tissue law and a volumetric penalty, for instance).
  std::vector<std::shared_ptr<const materials::StrainEnergy>> laws;
  /// Laws integrated with the one-point rule at the element centre, i.e. at the element's mean
  /// deformation gradient (selective reduced integration of a volumetric penalty, see above); they see
  /// the element's centre fiber frame.
  std::vector<std::shared_ptr<const materials::StrainEnergy>> centre_laws = {};
};

/// Per-element averages of the quantities one looks at in ParaView (docs/reference.md, "Hemodynamic
/// metrics"): J = det F, the fiber strain f0 . E f0 with E = (C - I)/2, the fiber stress f . sigma f with f =
/// F f0 / |F f0| and sigma = P F^T / J, the current fiber direction f; averaged over the element's quadrature
/// points with their weights. Fiber quantities are zero where f0 is zero. The Cauchy stress of the centre
/// laws (the volumetric penalty's pressure) is the element's filtered of its checkerboard mode
/// (SolidModel::filtered_centre_stress), added to sigma at every point.
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

/// The smallest J = det F over the points of the full rule, and the element it is in.
struct SmallestJacobian {
  double J = 0.0;
  int element = -1; ///< one element where J is smallest; -1 for a solid with no elements
};

class SolidModel {
 public:
  /// Keeps a reference to `mesh`, which must outlive the model.
  SolidModel(const Mesh& mesh, std::vector<BodyPart> parts, int quadrature_degree, MPI_Comm comm);

  const Mesh& mesh() const { return mesh_; }
  const QuadratureData& quadrature() const { return quadrature_; }
  /// The one-point rule of the centre laws (QuadratureData::element_means); nullptr when no part has
  /// centre laws.
  const QuadratureData* centre_quadrature() const { return centre_ ? &*centre_ : nullptr; }
  const std::vector<BodyPart>& parts() const { return parts_; }
  MPI_Comm comm() const { return comm_; }
  std::size_t num_dofs() const { return 3 * mesh_.num_nodes(); }

  /// Fiber frames, one per element (size num_elements) or one per quadrature point
  /// (size num_elements x points_per_element, element-major).
  void set_fibers(std::vector<materials::FiberFrame> fibers);
  const materials::FiberFrame& fibers(std::size_t e, int q) const;
  /// The frame the centre laws of element e see: the element's frame, or with frames per point their
  /// volume-weighted mean directions, normalised.
  const materials::FiberFrame& centre_fibers(std::size_t e) const;

  /// F at point q of element e for the replicated displacement u.
  Mat3 deformation_gradient(std::span<const double> u, std::size_t e, int q) const;
  /// The element's mean F, where its centre laws are evaluated (centre_quadrature() must exist).
  Mat3 centre_deformation_gradient(std::span<const double> u, std::size_t e) const
  {
    return deformation_gradient(*centre_, u, e, 0);
  }

  /// Nodal forces (replicated on every rank, summed over them). `forces` is overwritten. Without
  /// `centre_laws`, the full rule's laws alone: with the volumetric penalty as the centre law, the
  /// tissue's isochoric response (the stiffness the IB coupling's stability sees, ib/ibfe.hpp).
  void forces(std::span<const double> u, std::span<double> forces, bool centre_laws = true) const;
  /// Total strain energy (the same on every rank).
  double energy(std::span<const double> u) const;
  /// Adds this rank's element stiffness matrices to `K` (layout of `system`, 3 dofs per node); the
  /// caller assembles.
  void add_stiffness(std::span<const double> u, const NodalSystem& system, Mat K) const;
  /// The fields of ElementFields (replicated).
  ElementFields element_fields(std::span<const double> u) const;
  /// J, fiber strain and fiber stress at every quadrature point (replicated).
  PointFields point_fields(std::span<const double> u) const;
  /// The smallest J over every point of the full rule (the same on every rank; collective). A penalty
  /// integrated once per element holds each element's mean volume, not each point's, so a corner can
  /// collapse or invert (J <= 0) while the element's mean J stays near 1 (docs/fe.md, "Inverted
  /// element corners"): this is the figure that shows it.
  SmallestJacobian smallest_point_jacobian(std::span<const double> u) const;

  /// Cauchy stress of the centre laws of part p at the centre of element e (zero when it has none).
  Mat3 centre_cauchy_stress(int p, std::span<const double> u, std::size_t e) const;
  /// The centre laws' Cauchy stress of this rank's elements (indexed by element; zero elsewhere) with
  /// its checkerboard mode filtered out: each node takes the volume-weighted mean of its part's
  /// elements' centre stresses, each element the mean of its nodes'. A penalty integrated once per
  /// element is a constant pressure per element on trilinear displacements, the Q1-P0 pair, whose
  /// discrete divergence leaves the checkerboard pressure unconstrained: it alternates element by element
  /// without moving a node (Sani, Gresho, Lee & Griffiths 1981, Int. J. Numer. Methods Fluids 1:17,
  /// who filter it in the same way). The averaging zeroes a checkerboard and keeps a linear field in
  /// the interior of a uniform mesh. Output only: the forces use the element's own stress. Collective.
  std::vector<Mat3> filtered_centre_stress(std::span<const double> u) const;
  /// The (part, element) pairs this rank works on.
  std::span<const std::pair<int, int>> local_items() const { return local_items_; }

 private:
  /// F at point q of `rule` for element e.
  Mat3 deformation_gradient(const QuadratureData& rule, std::span<const double> u, std::size_t e,
                            int q) const;
  /// The frame a law integrated by `rule` sees at its point q.
  const materials::FiberFrame& frame(const QuadratureData& rule, std::size_t e, int q) const;
  /// A 3 x n matrix of nodal vectors of one element: n = N known at compile time, or Eigen::Dynamic.
  template <int N>
  using NodalMatrix = Eigen::Matrix<double, 3, N>;
  /// Sum over the points of `rule` of one element's forces, energy or stiffness for `laws`.
  template <int N>
  void add_element_forces(const QuadratureData& rule,
                          const std::vector<std::shared_ptr<const materials::StrainEnergy>>& laws,
                          std::size_t e, const NodalMatrix<N>& U, NodalMatrix<N>& element_forces) const;
  /// Adds this rank's element forces to `forces`, with N nodes per element (or Eigen::Dynamic).
  template <int N>
  void add_forces(std::span<const double> u, std::span<double> forces, bool centre_laws) const;
  double element_energy(const QuadratureData& rule,
                        const std::vector<std::shared_ptr<const materials::StrainEnergy>>& laws,
                        std::span<const double> u, std::size_t e) const;
  void add_element_stiffness(const QuadratureData& rule,
                             const std::vector<std::shared_ptr<const materials::StrainEnergy>>& laws,
                             std::span<const double> u, std::size_t e, Eigen::MatrixXd& element_matrix) const;

  const Mesh& mesh_;
  std::vector<BodyPart> parts_;
  QuadratureData quadrature_;
  std::optional<QuadratureData> centre_; ///< one point per element: the element means
  MPI_Comm comm_;
  std::vector<materials::FiberFrame> fibers_;
  bool fibers_per_point_ = false;
  std::vector<materials::FiberFrame> centre_fibers_; ///< with frames per point and centre laws
  std::vector<std::pair<int, int>> local_items_;
};

} // namespace ibvalve::fe
