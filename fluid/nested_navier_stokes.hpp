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
#include "fluid/flow_solver.hpp"
#include "fluid/grid.hpp"
#include "fluid/plane_region.hpp"
#include "fluid/settings.hpp"
#include "io/hdf5.hpp"

namespace ibvalve::fluid {

/// The composite gradient with quadratic coarse-fine interpolation (faces x cells, the face order of
/// `velocity`): same-level faces (p+ - p-)/h; a coarse-fine face differentiates at the face the quadratic
/// through the two fine cells behind it and the coarse value carried to the fine face's tangential
/// position by tensor quadratic interpolation along the interface (linear when the second fine cell is
/// itself covered). Annihilates constants. Caller destroys the matrix.
petsc::OwnedMat consistent_composite_gradient(const CompositeVelocity& velocity);

class NestedNavierStokes final : public FlowSolver {
 public:
  /// `wall_velocity(x, t)`: the velocity on the walls (its normal part must be zero); empty = no slip.
  /// A closed box: every side a velocity side.
  NestedNavierStokes(MPI_Comm comm, const GridHierarchy& hierarchy, VelocityFunction wall_velocity,
                     const FluidSettings& settings);
  /// Any velocity (u.n = 0) and traction sides; std::invalid_argument for a periodic side. The sides'
  /// functions are called during each step (a traction pressure may follow a Windkessel).
  NestedNavierStokes(MPI_Comm comm, const GridHierarchy& hierarchy, BoundaryConditions bc,
                     const FluidSettings& settings);
  NestedNavierStokes(const NestedNavierStokes&) = delete;
  NestedNavierStokes& operator=(const NestedNavierStokes&) = delete;

  const GridHierarchy& hierarchy() const { return *hierarchy_; }
  /// The composite numbering (two-point operators, Neumann sides) and the face velocity machinery.
  const CompositeOperators& operators() const { return *operators_; }
  const CompositeVelocity& composite_velocity() const { return *velocity_ops_; }
  const FluidSettings& settings() const { return settings_; }
  const BoundaryConditions& boundary_conditions() const { return bc_; }

  /// u(x, t) on the composite faces and p(x, t) as p^{n-1/2} (the first step's pressure guess).
  void set_initial_condition(const VelocityFunction& velocity, const ScalarFunction& pressure,
                             double t) override;
  /// The body force f^{n+1/2} on the composite faces (kept between steps).
  Vec body_force() { return force_.get(); }
  void set_body_force(const VelocityFunction& force, double t) override;

  void step(double dt) override;
  double time() const override { return time_; }
  /// The length of the last step (0 before the first; restored by load()).
  double last_step() const { return last_dt_; }
  double pressure_time() const override { return pressure_time_; }
  PetscInt steps_taken() const override { return stats_.steps; }
  /// Composite face velocity u^n (normal components) and composite cell pressure p^{n-1/2}.
  Vec velocity() const { return u_.get(); }
  Vec pressure() const { return p_.get(); }
  const StepStatistics& statistics() const override { return stats_; }
  /// The iterations of the last step's viscous solve and projection.
  PetscInt velocity_iterations() const { return velocity_iterations_; }
  PetscInt pressure_iterations() const { return pressure_iterations_; }
  std::vector<SolverFigure> last_solves() const override;
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
  void save(io::Hdf5File& file, const std::string& group) const override;
  /// Reads what save() wrote into this solver (same hierarchy). Collective; std::runtime_error naming
  /// the file and group when the checkpoint does not fit.
  void restore(const io::Hdf5File& file, const std::string& group) override;
  /// max |D u| over the composite cells of each level (D the projection's divergence).
  std::vector<double> max_divergence_by_level() const;
  /// Volume flux through a rectangle/disk: on a level-0 face plane the sum over its composite faces
  /// (composite_queries.hpp), between two such planes linear along the normal.
  double flux(const PlaneRegion& region) const override;
  /// p^{n-1/2} at the points `x` (probes): trilinear interpolation of the cell pressures of the finest level
  /// holding each point (cell centres outside that level's boxes or the domain: the nearest cell's value
  /// along that direction). Collective; the same values on every rank.
  std::vector<double> pressure_at(const std::vector<Real3>& x) const override;
  /// u^n at the points `x` (probes): trilinear interpolation of each component from the faces of the finest
  /// level holding the point, ghost faces as in CompositeVelocity. Collective; the same values on every rank.
  std::vector<Real3> velocity_at(const std::vector<Real3>& x) const override;
  /// 1/2 rho sum_f W_f u_f^2 over the composite faces (W_f each face's share of the volume).
  double kinetic_energy() const override;
  /// max |u_n| over the composite faces.
  double max_velocity() const override;
  /// The largest |u| of the cell-centred velocity (cell_velocity) over the composite cells whose centre
  /// `region` holds.
  double max_speed_in(const PointSet& region) const override;
  std::string describe() const override;
  double finest_spacing() const override;
  /// The composite pressure and cell-centred velocity of every level box (fluid/composite_output.hpp;
  /// covered cells averaged from the finer level), one XDMF grid a box.
  std::vector<io::XdmfGrid> write_fields(io::Hdf5File& file, const std::string& group,
                                         const std::string& file_reference) const override;

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
  // The constructor's steps, in its order.
  /// The composite operators of the chosen pressure coupling: G, G_d and the projection's M = G_d^T W G
  /// (with the constants as its null space in a closed box); returns the matrix the projection's
  /// preconditioner is built from.
  Mat build_operators();
  /// The projection's solver: GMRES (consistent coupling) or CG, BoomerAMG or the composite multigrid,
  /// its options prefixed by settings_.nested_prefix + "pressure_".
  void set_up_pressure_solver(Mat preconditioner);
  /// The viscous solve's GMRES with BoomerAMG, prefixed by settings_.nested_prefix + "velocity_".
  void set_up_velocity_solver();
  void advance(double dt, Vec convection_half);
  /// The boundary part c of the pressure gradient (G p + c) on the traction faces at time t, with the
  /// backflow drop from the current u_.
  void pressure_boundary_part(double t, Vec out) const;
  void build_helmholtz(double dt);
  void build_finest_level();
  /// Every rank's copy of p^{n-1/2} in composite order (collective).
  std::vector<double> gathered_pressure() const;

  MPI_Comm comm_;
  const GridHierarchy* hierarchy_;
  BoundaryConditions bc_;
  VelocityFunction wall_velocity_; // the velocity sides' data (zero on traction sides)
  FluidSettings settings_;
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
  petsc::OwnedVecScatter pressure_gather_; // p_ to every rank's copy (gathered_pressure) ...
  petsc::OwnedVec pressure_gathered_;      // ... held here
  petsc::OwnedVec convection_, convection_old_;
  double time_ = 0.0, pressure_time_ = 0.0, helmholtz_dt_ = 0.0, last_dt_ = 0.0;
  bool have_old_convection_ = false;
  StepStatistics stats_;
  PetscInt velocity_iterations_ = 0, pressure_iterations_ = 0;
  std::unique_ptr<StaggeredGrid> finest_;
  // Finest grid: for each local element and face slot, the composite value; for owned faces the index;
  // for each local element the composite cell (-1 outside the finest level).
  FaceValueTable finest_values_;
  std::vector<PetscInt> finest_owned_index_, finest_cells_;
  mutable std::vector<double> finest_buffer_; // finest_values_ evaluated
};

} // namespace ibvalve::fluid
