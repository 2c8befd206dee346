#pragma once
// Incompressible Navier–Stokes on the composite grid of nested levels (docs/nested.md, "The time step"):
// one time step for all levels together, a second-order pressure-increment projection method (Bell,
// Colella & Glaz 1989; Brown, Cortez & Minion 2001, J. Comput. Phys. 168:464, their "method II"):
//
//   (rho/dt - mu/2 L) u* = (rho/dt + mu/2 L) u^n - rho N^{n+1/2} - G p^{n-1/2} + f^{n+1/2}   (walls: u* = g)
//   M phi = D_int u*,   u^{n+1} = u* - G phi,   p^{n+1/2} = p^{n-1/2} + rho/dt phi - mu/2 (D G phi)
//
// L is the composite face Laplacian and N the convective term (centred by default, or limited upwind-biased)
// of fluid/composite_velocity.hpp; Crank–Nicolson and Adams–Bashforth 2 as on one level
// (fluid/navier_stokes.hpp; the first step is a Heun predictor-corrector). The velocity unknowns are the
// composite faces of CompositeOperators. The sides (fluid/boundary.hpp) are velocity sides with u.n = 0 (any
// tangential wall velocity g(x, t)) or traction sides (the pressure p_b(x, t) given, zero tangential
// velocity, du_n/dn = 0; walled where their `wall(x)` says so; backflow stabilization beta). On a traction
// face the normal velocity is an unknown (its ghost beyond the side even), the gradient there is
// (p_b - p)/(h/2) with p_b at t^{n+1/2} less the backflow drop beta rho/2 (u^n.n)_-^2, and the projection's
// phi is zero there (Dirichlet), so u^{n+1} sees p_b^{n+1/2}: the pressure-increment scheme with a given
// boundary pressure (Brown, Cortez & Minion 2001, section 4). Periodic sides are refused.
//
// The pressure coupling (PressureCoupling):
//  - `consistent` (default): D is the refluxed (two-point) composite divergence, exactly conservative
//    (the coarse flux through a coarse-fine face is the sum of its fine fluxes), and G is the gradient with
//    quadratic coarse-fine interpolation (coarse values carried quadratically along the interface, then a
//    quadratic through two fine cells and the coarse value along the normal; Martin & Colella 2000). The
//    projection operator M = D_int G (D_int = -V D) is not symmetric: GMRES preconditioned by BoomerAMG on
//    the symmetric two-point matrix G_tp^T W G_tp. Divergence zero to solver tolerance on every cell and the
//    flux through any closed surface of composite faces zero to solver tolerance.
//  - `adjoint`: G the tangential-linear composite gradient and D its adjoint (the symmetric pair of
//    fluid/composite_poisson.hpp), M = A symmetric, CG + BoomerAMG. Its O(h) gradient error at coarse-fine
//    faces limits the velocity to first order in max norm (measured in docs/nested.md).
//
// For the IB layer: the finest level must be one box; finest_level_grid() is a single-box StaggeredGrid
// over it (ghost width 2), velocity_to_finest() fills a local vector of that grid (ghost faces included:
// outside the box they are the coarse-fine interpolated values) and add_force_from_finest() adds a face
// force spread on that grid to the composite body force.
#include <memory>
#include <string>
#include <vector>

#include "fluid/boundary.hpp"
#include "fluid/composite_poisson.hpp"
#include "fluid/composite_velocity.hpp"
#include "fluid/grid.hpp"
#include "fluid/queries.hpp"
#include "io/hdf5.hpp"

namespace ibvalve::fluid {

enum class PressureCoupling { consistent, adjoint };

struct NestedFluidSettings {
  double rho = 1.0;
  double mu = 0.01;
  PressureCoupling coupling = PressureCoupling::consistent;
  // Centred by default: second order on every test; the limited scheme clips smooth extrema (docs/nested.md).
  ConvectionScheme convection = ConvectionScheme::centered;
  double velocity_rtol = 1e-12; // viscous solves (GMRES + BoomerAMG), options prefix <prefix>velocity_
  double pressure_rtol = 1e-12; // projection (GMRES or CG + BoomerAMG), options prefix <prefix>pressure_
  std::string prefix = "nested_";
};

struct NestedStepStatistics {
  PetscInt velocity_iterations = 0; // last viscous solve
  PetscInt pressure_iterations = 0; // last projection
  double seconds_convection = 0.0, seconds_velocity = 0.0, seconds_pressure = 0.0, seconds_total = 0.0;
  PetscInt steps = 0;
};

/// The composite gradient with quadratic coarse-fine interpolation (faces x cells, the face order of
/// `velocity`): same-level faces (p+ - p-)/h; a coarse-fine face differentiates at the face the quadratic
/// through the two fine cells behind it and the coarse value carried to the fine face's tangential
/// position by tensor quadratic interpolation along the interface (linear when the second fine cell is
/// itself covered). Annihilates constants. Caller destroys the matrix.
petsc::OwnedMat consistent_composite_gradient(const CompositeVelocity& velocity);

class NestedNavierStokes {
 public:
  /// `wall_velocity(x, t)`: the velocity on the walls (its normal part must be zero); empty = no slip.
  /// A closed box: every side a velocity side.
  NestedNavierStokes(MPI_Comm comm, const GridHierarchy& hierarchy, VelocityFunction wall_velocity,
                     const NestedFluidSettings& settings);
  /// Any velocity (u.n = 0) and traction sides; std::invalid_argument for a periodic side. The sides'
  /// functions are called during each step (a traction pressure may follow a Windkessel).
  NestedNavierStokes(MPI_Comm comm, const GridHierarchy& hierarchy, BoundaryConditions bc,
                     const NestedFluidSettings& settings);
  NestedNavierStokes(const NestedNavierStokes&) = delete;
  NestedNavierStokes& operator=(const NestedNavierStokes&) = delete;

  const GridHierarchy& hierarchy() const { return *hierarchy_; }
  /// The composite numbering (two-point operators, Neumann sides) and the face velocity machinery.
  const CompositeOperators& operators() const { return *operators_; }
  const CompositeVelocity& composite_velocity() const { return *velocity_ops_; }
  const NestedFluidSettings& settings() const { return settings_; }
  const BoundaryConditions& boundary_conditions() const { return bc_; }

  /// u(x, t) on the composite faces and p(x, t) as p^{n-1/2} (the first step's pressure guess).
  void set_initial_condition(const VelocityFunction& velocity, const ScalarFunction& pressure, double t);
  /// The body force f^{n+1/2} on the composite faces (kept between steps).
  Vec body_force() { return force_.get(); }
  void set_body_force(const VelocityFunction& force, double t);

  void step(double dt);
  double time() const { return time_; }
  double pressure_time() const { return pressure_time_; }
  PetscInt steps_taken() const { return stats_.steps; }
  /// Composite face velocity u^n (normal components) and composite cell pressure p^{n-1/2}.
  Vec velocity() const { return u_.get(); }
  Vec pressure() const { return p_.get(); }
  const NestedStepStatistics& statistics() const { return stats_; }
  /// True when the last step's viscous solve was preconditioned by Jacobi (the Helmholtz matrix's
  /// jacobi_ratio at most jacobi_ratio_limit, fluid/jacobi.hpp), not BoomerAMG.
  bool velocity_by_jacobi() const { return velocity_by_jacobi_; }

  /// The cell-centred velocity u^n (CompositeVelocity::cell_velocity) into three composite cell vectors
  /// (operators().create_cell_vector()). Collective.
  void cell_velocity(const std::array<Vec, 3>& out) const
  {
    velocity_ops_->cell_velocity(u_, wall_velocity_, time_, out);
  }
  /// Writes the state a step continues from into `group` of a checkpoint: u^n, p^{n-1/2}, N^n (for the
  /// Adams–Bashforth extrapolation), the body force, the clock and the step counter. Each vector in the
  /// composite numbering (cells, then each cell's faces in cell order), which does not depend on the
  /// rank count. Collective.
  void save(io::Hdf5File& file, const std::string& group) const;
  /// Reads what save() wrote into this solver (same hierarchy). Collective; std::runtime_error naming
  /// the file and group when the checkpoint does not fit.
  void restore(const io::Hdf5File& file, const std::string& group);
  /// max |D u| over the composite cells of each level (D the projection's divergence).
  std::vector<double> max_divergence_by_level() const;
  /// Volume flux through a rectangle/disk on a level-0 face plane (composite_queries.hpp).
  double flux(const PlaneRegion& region) const;
  /// p^{n-1/2} at the points `x` (probes): trilinear interpolation of the cell pressures of the finest level
  /// holding each point (cell centres outside that level's boxes or the domain: the nearest cell's value
  /// along that direction). Collective; the same values on every rank.
  std::vector<double> pressure_at(const std::vector<Real3>& x) const;
  /// u^n at the points `x` (probes): trilinear interpolation of each component from the faces of the finest
  /// level holding the point, ghost faces as in CompositeVelocity. Collective; the same values on every rank.
  std::vector<Real3> velocity_at(const std::vector<Real3>& x) const;

  /// The finest level as one StaggeredGrid (non-periodic, its own box; throws std::invalid_argument when
  /// the finest level has several boxes).
  const StaggeredGrid& finest_level_grid() const;
  /// Fills every face slot of `local` (a local vector of finest_level_grid(), ghosts included) with u^n
  /// and the cell slots of the owned cells with p^{n-1/2}. Collective.
  void velocity_to_finest(Vec local) const;
  /// Adds the face slots of the owned faces of `local` (a local vector of finest_level_grid(), e.g. what
  /// ib::Interaction::spread wrote) to body_force(). Collective.
  void add_force_from_finest(Vec local);

 private:
  void advance(double dt, Vec convection_half);
  /// The boundary part c of the pressure gradient (G p + c) on the traction faces at time t, with the
  /// backflow drop from the current u_.
  void pressure_boundary_part(double t, Vec out) const;
  void build_helmholtz(double dt);
  void build_finest_level();

  MPI_Comm comm_;
  const GridHierarchy* hierarchy_;
  BoundaryConditions bc_;
  VelocityFunction wall_velocity_; // the velocity sides' data (zero on traction sides)
  NestedFluidSettings settings_;
  std::unique_ptr<CompositeOperators> operators_, tangential_;
  std::unique_ptr<CompositeVelocity> velocity_ops_;
  petsc::OwnedMat gradient_;        // G: the gradient of the momentum equation and the projection
  petsc::OwnedMat divergence_;      // G_d: D_int = G_d^T W (D = -V^{-1} G_d^T W)
  petsc::OwnedMat projection_;      // M = G_d^T W G
  petsc::OwnedMat helmholtz_;       // rho/dt - mu/2 L
  bool velocity_by_jacobi_ = false; // the viscous solve's preconditioner is Jacobi (build_helmholtz)
  petsc::OwnedKSP velocity_ksp_, pressure_ksp_;
  petsc::OwnedMatNullSpace constants_;
  petsc::OwnedVec u_, p_, force_;
  petsc::OwnedVec convection_, convection_old_;
  double time_ = 0.0, pressure_time_ = 0.0, helmholtz_dt_ = 0.0, last_dt_ = 0.0;
  bool have_old_convection_ = false;
  NestedStepStatistics stats_;
  std::unique_ptr<StaggeredGrid> finest_;
  // Finest grid: for each local element and face slot, the composite value; for owned faces the index.
  std::vector<const FaceValue*> finest_values_;
  std::vector<PetscInt> finest_owned_index_;
};

} // namespace ibvalve::fluid
