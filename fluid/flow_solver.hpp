#pragma once
// The one interface of the incompressible flow solvers: what a run, the IB coupling's adapter
// (ib/eulerian_fluid.hpp) and the reports ask of a fluid, whatever its grid. Two solvers provide it:
// fluid::NavierStokes on one staggered grid (fluid/navier_stokes.hpp) and fluid::NestedNavierStokes on
// nested levels (fluid/nested_navier_stokes.hpp). Every query is collective over the solver's
// communicator and returns the same value on every rank.
#include <memory>
#include <string>
#include <vector>

#include <petscvec.h>

#include "fluid/boundary.hpp"
#include "fluid/plane_region.hpp"
#include "fluid/settings.hpp"
#include "io/hdf5.hpp"
#include "io/xdmf.hpp"

namespace ibvalve::fluid {

/// Wall-clock seconds spent in the parts of the steps so far, and their solver iterations.
struct StepStatistics {
  double convection = 0.0;
  double viscous = 0.0;  // explicit right side and the viscous (Helmholtz) solve
  double pressure = 0.0; // the pressure (Poisson/projection) solve and the rest of the coupled solve
  double halo = 0.0;     // ghost exchange and boundary ghosts (one grid)
  double total = 0.0;
  PetscInt steps = 0;
  PetscInt solver_iterations = 0; // summed over the steps and their iterative solves
};

/// One figure of the last step's solves, as diagnostics.csv (its column) and the progress line (its
/// label, when not empty) show it: "fluid it 7".
struct SolverFigure {
  std::string column;
  double value = 0.0;
  std::string label;
  std::string unit = "1"; ///< diagnostics.csv's units line: iteration counts and residuals are pure numbers
};

class FlowSolver {
 public:
  virtual ~FlowSolver() = default;

  virtual const FluidSettings& settings() const = 0;
  virtual const BoundaryConditions& boundary_conditions() const = 0;
  /// "grid 16 x 16 x 28" or "3 nested levels (...)": the grid, for the run's log.
  virtual std::string describe() const = 0;
  /// The smallest cell spacing, cm: the CFL number's.
  virtual double finest_spacing() const = 0;

  /// u(x, t) on the faces and p(x, t) as the first pressure (its guess); `pressure` may be empty (0).
  virtual void set_initial_condition(const VelocityFunction& velocity, const ScalarFunction& pressure,
                                     double t) = 0;
  /// The body force f^{n+1/2} of the next steps, sampled on the faces at time t (kept between steps).
  virtual void set_body_force(const VelocityFunction& force, double t) = 0;
  /// Advances from time() to time() + dt.
  virtual void step(double dt) = 0;
  virtual double time() const = 0;
  /// The time of the pressure: time() - dt/2 after a step.
  virtual double pressure_time() const = 0;
  virtual PetscInt steps_taken() const = 0;

  /// Writes everything step() reads into `group` of a checkpoint, in a layout that does not depend on
  /// the rank count; restore() reads it back (the same grid; any rank count). Collective.
  virtual void save(io::Hdf5File& file, const std::string& group) const = 0;
  virtual void restore(const io::Hdf5File& file, const std::string& group) = 0;

  /// Volume flux int u.n dA of u^n over the region.
  virtual double flux(const PlaneRegion& region) const = 0;
  /// p at pressure_time() at the points (probes), trilinear from the cell centres.
  virtual std::vector<double> pressure_at(const std::vector<Real3>& points) const = 0;
  /// u^n at the points (probes), trilinear from the faces.
  virtual std::vector<Real3> velocity_at(const std::vector<Real3>& points) const = 0;
  /// 1/2 rho int |u^n|^2, erg.
  virtual double kinetic_energy() const = 0;
  /// The largest speed, cm/s (the CFL number's).
  virtual double max_velocity() const = 0;
  /// The largest speed |u^n| at the cell centres that `region` holds, cm/s (each component the mean of
  /// the cell's two faces); 0 when it holds none. A peak velocity measured where the flow of interest
  /// is (the report's jet), not wherever in the box the flow is fastest.
  virtual double max_speed_in(const PointSet& region) const = 0;
  /// Writes the cell-centred velocity and the pressure (and what else the solver has) into `group` of
  /// a field snapshot and returns their XDMF grids; `file_reference` is the HDF5 file as the XDMF file
  /// names it. Collective.
  virtual std::vector<io::XdmfGrid> write_fields(io::Hdf5File& file, const std::string& group,
                                                 const std::string& file_reference) const = 0;

  virtual const StepStatistics& statistics() const = 0;
  /// The iterations (and residuals) of the last step's solves.
  virtual std::vector<SolverFigure> last_solves() const = 0;
};

class GridHierarchy;

/// The solver of a case: fluid::NestedNavierStokes on `levels` when given (the box is their level 0),
/// else fluid::NavierStokes on `box`. std::invalid_argument for sides the solver does not take.
std::unique_ptr<FlowSolver> make_flow_solver(MPI_Comm comm, const BoxGeometry& box,
                                             const GridHierarchy* levels, BoundaryConditions bc,
                                             const FluidSettings& settings);

} // namespace ibvalve::fluid
