#pragma once
// The coupled Stokes solver for any boundary conditions (see fluid/stokes_solver.hpp): the system is
// assembled as one PETSc matrix on the staggered grid and solved by FGMRES, preconditioned by the
// projection method with one multigrid cycle for each sub-problem (Griffith 2009, JCP 228:7565):
//
//   u* = H^-1 w,  r = -D u* - g,  phi = K^-1 r (K = -D G),  u = u* - G phi,  p = rho/dt phi + mu/2 r.
//
// Discretisation at the box sides (fluid/boundary.hpp): on a velocity side the boundary normal
// velocity is a fixed unknown (identity row) and tangential components use the ghost
// 8/3 g - 2 u_0 + 1/3 u_1 (quadratic extrapolation through the wall value, exact for parabolas);
// on a traction side the boundary normal velocity is an unknown whose momentum equation uses the
// even ghost (du_n/dn = 0) and the one-sided pressure gradient (p_in - p_b)/(h/2), and tangential
// components the same ghost with g = 0 (no slip). Options prefixes: fluid_stokes_ (FGMRES), fluid_helmholtz_
// and fluid_poisson_ (default: one hypre BoomerAMG V-cycle each; with settings.subsolver = fft the
// FFTW transform solves of fluid/transform_subsolvers.hpp, exact for K, a spectrally equivalent
// preconditioner for H when a velocity component has a tangential wall). Blocked cells of a solid region
// (fluid/solid_cells.hpp) are identity rows; with them the Poisson sub-solve is the exact axial solve of
// fluid/axial_poisson.hpp where the blocked cells are the same in every z-plane (-fluid_poisson_pc_type
// hypre: BoomerAMG), BoomerAMG otherwise (the transforms know only the box), and the Helmholtz sub-solve
// Jacobi sweeps or BoomerAMG.
#include <memory>
#include <vector>

#include <petscksp.h>

#include "fluid/axial_poisson.hpp"
#include "fluid/settings.hpp"
#include "fluid/solid_cells.hpp"
#include "fluid/stokes_solver.hpp"
#include "fluid/transform_subsolvers.hpp"

namespace ibvalve::fluid {

class KrylovStokesSolver : public StokesSolver {
 public:
  /// `bc` is kept by reference: its boundary data is read at every solve.
  KrylovStokesSolver(const StaggeredGrid& grid, const BoundaryConditions& bc, const FluidSettings& settings);
  // `this` is the context of the PCShell preconditioners: the solver must stay where it was built.
  KrylovStokesSolver(const KrylovStokesSolver&) = delete;
  KrylovStokesSolver& operator=(const KrylovStokesSolver&) = delete;
  KrylovStokesSolver(KrylovStokesSolver&&) = delete;
  KrylovStokesSolver& operator=(KrylovStokesSolver&&) = delete;

  void set_parameters(const StokesParameters& parameters) override;
  SolveStatistics solve(Vec rhs, Vec solution) override;
  void add_boundary_terms(Vec rhs, double t_new, double t_half) override;
  void set_homogeneous_boundary_rows(Vec rhs) override;
  std::string name() const override
  {
    return transforms_used_ ? "krylov (fft sub-solves)"
           : solid_.empty() ? "krylov"
           : axial_         ? "krylov (blocked cells, axial Poisson)"
                            : "krylov (blocked cells)";
  }

  /// With transform sub-solves the Helmholtz block is solved by `jacobi_sweeps` Jacobi sweeps when
  /// its jacobi_ratio is at most jacobi_ratio_limit (fluid/jacobi.hpp; the option
  /// -fluid_helmholtz_jacobi_limit sets another limit, 0: the transforms always); otherwise by the
  /// transforms.
  static constexpr int jacobi_sweeps = 2;
  /// True when set_parameters chose Jacobi sweeps for the Helmholtz block.
  bool helmholtz_by_jacobi() const { return helmholtz_by_jacobi_; }

  /// The assembled operator, its velocity block H and the pressure Poisson operator K = -D G, and
  /// the sub-solvers applied to them in the preconditioner (for tests; valid after set_parameters).
  Mat matrix() const { return A_; }
  Mat helmholtz_matrix() const { return H_; }
  Mat poisson_matrix() const { return K_; }
  KSP helmholtz_ksp() const { return ksp_h_; }
  KSP poisson_ksp() const { return ksp_k_; }
  IS velocity_set() const { return is_u_; }
  IS pressure_set() const { return is_p_; }
  /// The blocked cells of the solid region (empty without one).
  const SolidCells& solid() const { return solid_; }
  /// The transform sub-solvers (null unless settings.subsolver is fft and no cell is blocked).
  const TransformSubsolvers* transforms() const { return transforms_.get(); }
  /// The exact axial Poisson solve, when the blocked cells allow it (else nullptr).
  const AxialPoisson* axial_poisson() const { return axial_.get(); }

 private:
  struct Entry {
    DMStagStencil column;
    double value;
  };
  /// One row of the system: its entries and the constant the boundary data adds to the right side
  /// (moved there with its sign). Returns true for a Dirichlet row (rhs = constant, not added).
  bool velocity_row(int d, const Index3& idx, double t_new, double t_half, std::vector<Entry>& entries,
                    double& constant) const;
  void pressure_row(const Index3& idx, std::vector<Entry>& entries) const;
  void assemble(Mat matrix) const;
  /// Blocked cells: K = -D G has empty rows there (their faces are identity rows); adds an identity to K
  /// there and makes fluid_cells_, the pressure block's indicator of the fluid cells.
  void regularise_blocked_cells();
  /// The outer FGMRES with the projection preconditioner (options prefix fluid_stokes_).
  void make_outer_solver();
  /// A new dt with the same rho and mu: the operators' diagonals updated in place (true), or false when
  /// they must be built anew (nothing built yet, rho or mu changed, or the Helmholtz sub-solver changes
  /// kind).
  bool change_step(const StokesParameters& parameters);
  /// Whether the Helmholtz block H (assembled) is to be inverted by Jacobi sweeps.
  bool helmholtz_wants_jacobi() const;
  void destroy();
  static PetscErrorCode apply_projection(PC pc, Vec x, Vec y);
  static PetscErrorCode apply_helmholtz_transform(PC pc, Vec x, Vec y);
  static PetscErrorCode apply_poisson_transform(PC pc, Vec x, Vec y);
  static PetscErrorCode apply_axial_poisson(PC pc, Vec x, Vec y);

  const StaggeredGrid& grid_;
  const BoundaryConditions& bc_;
  FluidSettings settings_;
  StokesParameters parameters_{};
  bool pressure_has_constant_ = true;
  SolidCells solid_;
  bool transforms_used_ = false; // the transform sub-solves (settings.subsolver fft, no blocked cell)
  petsc::OwnedMat A_, H_, G_, Dn_, K_;
  petsc::OwnedIS is_u_, is_p_;
  petsc::OwnedKSP ksp_, ksp_h_, ksp_k_;
  petsc::OwnedVec x_, b_, r_p_, phi_, gphi_;
  petsc::OwnedVec x_u_, y_u_, x_p_, y_p_; // the preconditioner's blocks
  petsc::OwnedVec fluid_cells_; // pressure block: 1 on fluid cells, 0 on blocked ones (with a solid)
  double helmholtz_seconds_ = 0.0, poisson_seconds_ = 0.0;
  bool helmholtz_by_jacobi_ = false;
  // Built once (FFTW plans, scatters): they depend on the grid and the side kinds, not on dt.
  std::unique_ptr<TransformSubsolvers> transforms_;
  // Blocked cells the same in every z-plane: the exact Poisson solve (built with K).
  std::unique_ptr<AxialPoisson> axial_;
};

} // namespace ibvalve::fluid
