#include "ib/nodal_mass.hpp"

#include "io/errors.hpp"
#include "io/petsc_check.hpp"

namespace ibvalve::ib {

NodalMass::NodalMass(const fe::Mesh& mesh, fe::MassKind kind, MPI_Comm comm, const std::string& prefix)
    : mesh_(mesh), kind_(kind), quadrature_(mesh, 2), system_(mesh, 1, comm)
{
  // Degree 2 integrates N_a N_b exactly on affine tetrahedra and on parallelepiped hexahedra.
  lumped_ = fe::lumped_mass(mesh, quadrature_, comm);
  if (kind_ == fe::MassKind::lumped) return;
  mass_ = fe::consistent_mass_matrix(mesh, quadrature_, system_);
  PETSC_CHECK(KSPCreate(comm, &ksp_));
  PETSC_CHECK(KSPSetOptionsPrefix(ksp_, prefix.c_str()));
  PETSC_CHECK(KSPSetOperators(ksp_, mass_, mass_));
  PETSC_CHECK(KSPSetType(ksp_, KSPCG));
  PC pc;
  PETSC_CHECK(KSPGetPC(ksp_, &pc));
  PETSC_CHECK(PCSetType(pc, PCJACOBI));
  PETSC_CHECK(KSPSetTolerances(ksp_, 1e-13, 1e-300, PETSC_DEFAULT, 1000));
  PETSC_CHECK(KSPSetFromOptions(ksp_));
  x_ = system_.create_vector();
  b_ = system_.create_vector();
}

NodalMass::~NodalMass()
{
  if (x_) VecDestroy(&x_);
  if (b_) VecDestroy(&b_);
  if (ksp_) KSPDestroy(&ksp_);
  if (mass_) MatDestroy(&mass_);
}

std::vector<double> NodalMass::solve(std::span<const double> b) const
{
  const std::size_t nodes = mesh_.num_nodes();
  std::vector<double> v(3 * nodes, 0.0);
  if (kind_ == fe::MassKind::lumped) {
    for (std::size_t n = 0; n < nodes; ++n)
      for (int c = 0; c < 3; ++c) v[3 * n + c] = b[3 * n + c] / lumped_[n];
    return v;
  }
  iterations_ = 0;
  std::vector<double> component(nodes);
  for (int c = 0; c < 3; ++c) {
    for (std::size_t n = 0; n < nodes; ++n) component[n] = b[3 * n + c];
    system_.scatter(component, b_);
    PETSC_CHECK(KSPSolve(ksp_, b_, x_));
    KSPConvergedReason reason;
    PETSC_CHECK(KSPGetConvergedReason(ksp_, &reason));
    if (reason < 0) throw RunError("ib: the mass-matrix solve (L2 projection) did not converge");
    PetscInt its = 0;
    PETSC_CHECK(KSPGetIterationNumber(ksp_, &its));
    iterations_ += its;
    const std::vector<double> x = system_.gather(x_);
    for (std::size_t n = 0; n < nodes; ++n) v[3 * n + c] = x[n];
  }
  return v;
}

} // namespace ibvalve::ib
