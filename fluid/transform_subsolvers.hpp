#pragma once
// Transform sub-solves for the projection preconditioner of the Krylov Stokes solver
// (fluid/krylov_stokes.hpp, `fluid.subsolver = "fft"`), on the uniform box with any mix of periodic,
// velocity and traction sides (fluid/transform_solver.hpp does the transforms):
//
// - Pressure Poisson K = -D G on cell centres, exactly: a velocity side holds the boundary normal
//   velocity fixed, so G has no row there and K is closed by a homogeneous Neumann condition; a
//   traction side's gradient (p_in - p_b)/(h/2) makes it a Dirichlet condition at the side. Where a
//   z side is a traction side walled in part, a capacitance-matrix correction keeps the solve exact
//   (fluid/walled_side_capacitance.hpp); walled parts of x or y sides are not corrected (the solve is
//   then a preconditioner there).
// - Helmholtz H = rho/dt - mu/2 L for each velocity component. Along the component's own direction
//   the discretisation is separable (velocity side: a fixed boundary node whose value moves to the
//   right side, Dirichlet; traction side: the even ghost, Neumann), so that part is exact. Along
//   the tangential directions the assembled operator uses the quadratic wall ghost
//   8/3 g - 2 u_0 + 1/3 u_1, which no sine transform diagonalises; the transform uses the linear
//   ghost -u_0 (Dirichlet at the side) there, a spectrally equivalent operator (they differ in the
//   first cell only, by a bounded factor of the near-wall stencil), so FGMRES still converges in a
//   few iterations independent of the grid. With no tangential wall (a box periodic except along the
//   component) the Helmholtz solve is exact too.
//
// Data moves between the PETSc sub-vectors (any DMStag decomposition) and FFTW's z slabs by
// VecScatters built once.
#include <array>
#include <memory>

#include <petscmat.h>

#include "fluid/boundary.hpp"
#include "fluid/grid.hpp"
#include "fluid/transform_solver.hpp"
#include "fluid/walled_side_capacitance.hpp"

namespace ibvalve::fluid {

class TransformSubsolvers {
 public:
  /// `velocity` and `pressure`: the index sets of the face and cell unknowns in the grid's global
  /// vector (the layouts of the sub-vectors the solves take).
  TransformSubsolvers(const StaggeredGrid& grid, const BoundaryConditions& bc, IS velocity, IS pressure);
  TransformSubsolvers(const TransformSubsolvers&) = delete;
  TransformSubsolvers& operator=(const TransformSubsolvers&) = delete;

  /// phi = K^-1 r. Without a traction side K is singular: r must have zero mean, phi gets zero mean.
  void solve_poisson(Vec r, Vec phi);
  /// u = H~^-1 w for H = a I - b L (a = rho/dt, b = mu/2). `H` is the assembled velocity block, used
  /// only to move the fixed boundary normal velocities (identity rows) to the right side.
  void solve_helmholtz(Mat H, double a, double b, Vec w, Vec u);

  /// True when the Helmholtz transform solve is exact (no velocity component has a tangential wall).
  bool helmholtz_exact() const { return helmholtz_exact_; }
  /// True when the Poisson solve is exact (no x or y traction side is walled in part, and z sides walled
  /// in part are corrected: not with -fluid_poisson_capacitance false).
  bool poisson_exact() const { return poisson_exact_; }
  /// The walled-z-side correction of the Poisson solve (null without walled z sides).
  const WalledSideCapacitance* capacitance() const { return capacitance_.get(); }

 private:
  struct Problem {
    std::unique_ptr<SeparableTransformSolver> solver;
    petsc::OwnedVec transformed;    // the solver's slab as a PETSc vector
    petsc::OwnedVecScatter scatter; // sub-vector -> slab
  };
  void build(Problem& problem, const std::array<TransformAxis, 3>& axes, Vec sub, const Vec codes,
             PetscInt kind, Vec dirichlet_mask);

  const StaggeredGrid& grid_;
  Problem pressure_;
  std::unique_ptr<WalledSideCapacitance> capacitance_;
  std::array<Problem, 3> velocity_;
  petsc::OwnedVec dirichlet_, fixed_, work_;
  bool helmholtz_exact_ = true;
  bool poisson_exact_ = true;
};

} // namespace ibvalve::fluid
