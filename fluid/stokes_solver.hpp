#pragma once
// Solvers for the Stokes system of one time step,
//
//     (rho/dt - mu/2 L) u + G p = w        (momentum, on faces)
//                        -D u   = g        (continuity, on cells)
//
// with the boundary conditions built into L, G and D (fluid/boundary.hpp). Two solvers:
// - FftStokesSolver: periodic boxes. On a uniform periodic MAC grid L, G and D are circulant and
//   commute (D G = L on cells, G D = L on curl-free parts), so the projection method is exact:
//   u* = H^-1 w, phi = L^-1 (D u*), u = u* - G phi, p = rho/dt phi - mu/2 D u*.
//   Every step is a scalar multiplication per Fourier mode (FFTW-MPI, slab decomposition in z).
//   It takes g = 0 (the cell slots of the right side are not read): on a periodic box the
//   Navier–Stokes step always has a divergence-free target.
// - KrylovStokesSolver: any boundary conditions. The coupled system is assembled (PETSc AIJ) and
//   solved by FGMRES preconditioned by the same projection method with inexact sub-solves
//   (hypre BoomerAMG V-cycles on the Helmholtz block H and on the pressure Poisson operator D G, or
//   FFTW sine/cosine transform solves, fluid/transform_subsolvers.hpp), the preconditioner of
//   Griffith (2009, JCP 228:7565, section 4). Options prefix "fluid_stokes_"
//   for the outer solver, "fluid_helmholtz_" and "fluid_poisson_" for the sub-solves.
#include <string>

#include <petscksp.h>

#include "fluid/boundary.hpp"
#include "fluid/grid.hpp"

namespace ibvalve::fluid {

struct StokesParameters {
  double rho = 1.0;
  double mu = 0.01;
  double dt = 0.01;
};

struct SolveStatistics {
  PetscInt iterations = 0;        // outer iterations (0 for a direct FFT solve)
  double residual = 0.0;          // final (preconditioned) residual norm
  double helmholtz_seconds = 0.0; // time in the velocity (Helmholtz) part
  double poisson_seconds = 0.0;   // time in the pressure (Poisson) part
};

class StokesSolver {
 public:
  virtual ~StokesSolver() = default;
  /// Called when rho, mu or dt change (and once before the first solve).
  virtual void set_parameters(const StokesParameters& parameters) = 0;
  /// `rhs` (local vector): face slots hold w, cell slots hold g, including the boundary terms of
  /// time level n+1 (see NavierStokes). `solution` (local vector) receives u on every owned face and
  /// p on every owned cell; on entry it holds the initial guess for iterative solvers.
  virtual SolveStatistics solve(Vec rhs, Vec solution) = 0;
  /// Adds to `rhs` what the boundary conditions contribute to the implicit side: velocity data at
  /// t_new (Dirichlet rows, wall ghosts of the implicit Laplacian) and boundary pressures at t_half.
  virtual void add_boundary_terms(Vec /*rhs*/, double /*t_new*/, double /*t_half*/) {}
  /// What add_boundary_terms does for zero boundary data: the rows that hold a boundary value
  /// (Dirichlet rows) set to 0, the others left as they are.
  virtual void set_homogeneous_boundary_rows(Vec /*rhs*/) {}
  virtual std::string name() const = 0;
};

} // namespace ibvalve::fluid
