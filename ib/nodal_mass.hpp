#pragma once
// Solves M v = b for 3-component nodal fields of the replicated structure mesh, with the consistent
// mass matrix M_ab = int N_a N_b dX or the row-sum lumped mass m_a = int N_a dX: the L2 projections
// of the IB/FE coupling (velocity to nodes, nodal force to force density). Both are exact for a
// constant field; the consistent one for every field in the finite-element space.
//
// The mesh is replicated and the right-hand sides are summed over the ranks before a solve, so each
// rank solves the same small system by itself (PETSC_COMM_SELF), with no communication. By default a
// sparse Cholesky factorization made once (CHOLMOD through PETSc, simplicial, with CHOLMOD's own
// fill-reducing ordering), and the three components of a field solved as the three columns of one
// right-hand side, carried through the factor together (KSPMatSolve). The options prefix selects any
// other PETSc solve (-ib_velocity_mass_pc_factor_mat_solver_type petsc, or -ib_velocity_mass_ksp_type cg
// -ib_velocity_mass_pc_type jacobi); an iterative one solves component by component, each starting from
// the last solution of the same field (its "guess slot"), since that changes little from step to step.
#include <span>
#include <string>
#include <vector>

#include <petscksp.h>

#include "fe/mass.hpp"
#include "fe/nodal_system.hpp"
#include "fe/quadrature_data.hpp"
#include "io/hdf5.hpp"
#include "io/petsc_handle.hpp"

namespace ibvalve::ib {

class NodalMass {
 public:
  NodalMass(const fe::Mesh& mesh, fe::MassKind kind, MPI_Comm comm, const std::string& prefix = "ib_mass_");
  NodalMass(const NodalMass&) = delete;
  NodalMass& operator=(const NodalMass&) = delete;

  fe::MassKind kind() const { return kind_; }
  /// int N_a dX, replicated.
  const std::vector<double>& lumped() const { return lumped_; }
  /// v with M v = b, both replicated and interlaced (3 per node). An iterative consistent solve starts
  /// from the last solution stored in `guess_slot` (0, 1, 2, ...); every consistent solve stores its own
  /// there. Every rank solves the same system and stops alike when it fails.
  std::vector<double> solve(std::span<const double> b, int guess_slot = 0) const;
  /// Krylov iterations of the last consistent solve, summed over the components (1 each when direct).
  PetscInt last_iterations() const { return iterations_; }

  /// Writes the stored solutions the iterative solves start from (the guess slots) into `group` of a
  /// checkpoint, so a restarted run starts each solve where the uninterrupted one would. Collective.
  void save(io::Hdf5File& file, const std::string& group) const;
  void restore(const io::Hdf5File& file, const std::string& group);

 private:
  const fe::Mesh& mesh_;
  fe::MassKind kind_;
  fe::QuadratureData quadrature_;
  fe::NodalSystem system_;
  std::vector<double> lumped_;
  petsc::OwnedMat mass_;
  petsc::OwnedKSP ksp_;
  bool direct_ = true;  // a factorization (KSPPREONLY), solved for the three columns at once
  petsc::OwnedMat rhs_; // dense, nodes x 3: the components as columns
  mutable std::vector<petsc::OwnedMat> guesses_; // per slot: dense, nodes x 3
  mutable PetscInt iterations_ = 0;
};

} // namespace ibvalve::ib
