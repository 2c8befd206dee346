#pragma once
// The incompressible Navier–Stokes integrator on the staggered grid:
//
//   rho (u^{n+1} - u^n)/dt + G p^{n+1/2} = mu/2 L (u^{n+1} + u^n) - rho N^{n+1/2} + f^{n+1/2}
//                             -D u^{n+1} = 0
//
// Crank–Nicolson viscous term, convection N = div(u u) (fluid/convection.hpp) extrapolated by
// Adams–Bashforth 2, N^{n+1/2} = (1 + r/2) N^n - r/2 N^{n-1} with r = dt_n / dt_{n-1}; the first step
// is a predictor-corrector (Heun: N^{1/2} = (N(u^0) + N(u~^1))/2), so every step is second order.
// The coupled Stokes system for (u^{n+1}, p^{n+1/2}) is solved each step (fluid/stokes_solver.hpp);
// the pressure is therefore at half steps. f is the external body force on the faces (what the IB
// method spreads), set before each step.
#include <memory>
#include <string>
#include <vector>

#include "fluid/boundary.hpp"
#include "fluid/convection.hpp"
#include "fluid/flow_solver.hpp"
#include "fluid/grid.hpp"
#include "fluid/settings.hpp"
#include "fluid/solid_cells.hpp"
#include "fluid/stokes_solver.hpp"
#include "io/hdf5.hpp"

namespace ibvalve::fluid {

class NavierStokes final : public FlowSolver {
 public:
  NavierStokes(MPI_Comm comm, const BoxGeometry& box, BoundaryConditions bc, const FluidSettings& settings);
  NavierStokes(const NavierStokes&) = delete;
  NavierStokes& operator=(const NavierStokes&) = delete;

  const StaggeredGrid& grid() const { return *grid_; }
  const BoundaryConditions& boundary_conditions() const override { return bc_; }
  /// Boundary data may change during a run (e.g. a Windkessel pressure): edit the sides through this.
  BoundaryConditions& boundary_conditions() { return bc_; }
  const FluidSettings& settings() const override { return settings_; }
  const StokesSolver& solver() const { return *solver_; }

  /// Sets u(x, 0) on the faces (and p, for output and as a first guess) at time t.
  void set_initial_condition(const VelocityFunction& velocity, const ScalarFunction& pressure,
                             double t) override;

  /// The body force f^{n+1/2} for the next step, a local vector: fill its face slots (owned faces).
  /// It is kept (not cleared) between steps.
  Vec body_force() { return force_.get(); }
  void set_body_force(const VelocityFunction& force, double t) override;

  /// Advances from time() to time() + dt.
  void step(double dt) override;

  /// The velocity one step of dt gives a body force `force` (the face slots of a local vector) from rest
  /// with homogeneous boundary data, no convection: (rho/dt - mu/2 L) u + G p = f, -D u = 0, the linear
  /// part of a step's response to its body force. `velocity` (a local vector) receives u (ghosts from
  /// the neighbouring ranks filled; the sides' ghosts not). The state is not touched. Collective.
  void stokes_response(Vec force, double dt, Vec velocity);
  /// Adds `increment` (a local vector: face velocities and cell pressures, e.g. a stokes_response) to
  /// the state u^n, p^{n-1/2} and refills the ghosts: the step's solution being linear in its body
  /// force, a step taken without a force plus the response to one is the step taken with it.
  void add_to_state(Vec increment);

  double time() const override { return time_; }
  /// The length of the last step (0 before the first; restored by load()).
  double last_step() const { return last_dt_; }
  PetscInt steps_taken() const override { return steps_; }
  /// The state as a local vector: face slots u^n (ghosts filled, boundary conditions applied), cell
  /// slots p^{n-1/2} (ghosts filled). Read-only for callers; valid until the next step().
  Vec state() const { return state_.get(); }
  /// The time at which pressure() lives: time() - dt/2 after a step.
  double pressure_time() const override { return pressure_time_; }
  const StepStatistics& statistics() const override { return statistics_; }
  const SolveStatistics& last_solve() const { return last_solve_; }

  /// Writes everything step() reads into `group` of a checkpoint (collective): u^n and p^{n-1/2}, the
  /// convection term N^n that Adams–Bashforth 2 needs as N^{n-1} next step, the body force, and the
  /// clock (time, pressure time, last step, step count). Grid fields are (z, y, x, 4) arrays of
  /// (u_x, u_y, u_z, p) per element over (N + 1) elements in each non-periodic direction (the extra
  /// face layer; slots that do not exist there hold 0), so the layout does not depend on the ranks.
  void save(io::Hdf5File& file, const std::string& group) const override;
  /// Reads what save() wrote into this solver (same box and cells; any rank count). Call it once the
  /// boundary conditions are those of the checkpoint's time: the ghosts are refilled from them. On
  /// the same rank count, the steps that follow equal those of the uninterrupted run bit for bit.
  void restore(const io::Hdf5File& file, const std::string& group) override;

  // The rest of FlowSolver, through fluid/queries.hpp and fluid/output.hpp.
  std::string describe() const override;
  double finest_spacing() const override;
  double flux(const PlaneRegion& region) const override;
  std::vector<double> pressure_at(const std::vector<Real3>& points) const override;
  std::vector<Real3> velocity_at(const std::vector<Real3>& points) const override;
  double kinetic_energy() const override;
  double max_velocity() const override;
  double max_speed_in(const PointSet& region) const override;
  std::vector<io::XdmfGrid> write_fields(io::Hdf5File& file, const std::string& group,
                                         const std::string& file_reference) const override;
  /// The FGMRES iterations and residual of the last step (0 for the direct FFT solve).
  std::vector<SolverFigure> last_solves() const override;

 private:
  void exchange(double t);
  /// The backflow pressure drops of the traction sides with backflow stabilization, from state_.
  void update_backflow_drop();
  void explicit_rhs(Vec convection_half, double dt);

  MPI_Comm comm_;
  BoundaryConditions bc_;
  FluidSettings settings_;
  std::unique_ptr<StaggeredGrid> grid_;
  std::unique_ptr<StokesSolver> solver_;
  const SolidCells* solid_ = nullptr; // the Krylov solver's blocked cells (fluid/solid_cells.hpp)
  petsc::OwnedVec state_, force_, rhs_, response_rhs_;
  petsc::OwnedVec convection_, convection_old_, convection_half_, saved_;
  double time_ = 0.0, pressure_time_ = 0.0, last_dt_ = 0.0;
  PetscInt steps_ = 0;
  bool have_old_convection_ = false;
  StokesParameters parameters_{0.0, 0.0, 0.0}; // dt 0: the first step sets the solver up
  StepStatistics statistics_;
  SolveStatistics last_solve_;
};

} // namespace ibvalve::fluid
