#pragma once
// The fluid as the IB/FE integrator sees it (ib/ibfe.hpp): one distributed single-box staggered grid on
// which the structure's velocity is interpolated and its force spread, a velocity u^n on that grid, a
// way to hand a spread force to the fluid as f^{n+1/2}, and the time step. Two fluids provide it:
//  - UniformFluid: fluid::NavierStokes on one grid; the grid, its state and its body force are used in
//    place (no copies), so a coupled run is the same as before this interface existed, bit for bit.
//  - NestedFluid: fluid::NestedNavierStokes on nested levels; the structure lives on the finest level
//    only (docs/nested.md, "IB on the finest level"): u^n is copied from the composite grid to a local
//    vector of finest_level_grid() (ghost faces outside the finest box hold the coarse-fine interpolated
//    values) after every step, and the force spread on that grid is added to the composite body force,
//    which is otherwise zero. A structure node that comes closer to the finest box's edge than the
//    kernel's half support stops the run (RunError): read_hierarchy places the level with that room.
// fluid/ knows nothing of the structure; this file is the only place where the two meet.
#include <memory>
#include <span>
#include <string>

#include <petscvec.h>

#include "fluid/grid.hpp"
#include "ib/interaction.hpp"

namespace ibvalve::fluid {
class FlowSolver;
class NavierStokes;
class NestedNavierStokes;
} // namespace ibvalve::fluid

namespace ibvalve::ib {

class EulerianFluid {
 public:
  virtual ~EulerianFluid() = default;

  /// The grid the structure interpolates from and spreads to.
  virtual const fluid::StaggeredGrid& grid() const = 0;
  /// u^n as a local vector of grid() (face slots, ghosts filled). Valid until the next step().
  virtual Vec velocity() const = 0;
  /// A local vector of grid() whose owned face slots the spreading writes (overwrites) ...
  virtual Vec force() = 0;
  /// ... and that becomes the fluid's body force f^{n+1/2} of the next step by this call. Collective.
  virtual void apply_force() = 0;
  /// Advances the fluid from time() to time() + dt with the body force of apply_force().
  virtual void step(double dt) = 0;
  virtual double time() const = 0;
  /// The length of the last step (0 before the first): the one the fluid's solvers are set up for.
  virtual double last_step() const = 0;
  virtual double density() const = 0;
  virtual double viscosity() const = 0;
  /// RunError when a node of the structure (current positions) lies where the IB cannot follow it: on
  /// nested grids, closer than `reach` cells (the kernel's half support) to the finest level's edge,
  /// where the kernel would be cut off. The walls of one grid are checked by GridInteraction.
  virtual void require_inside(std::span<const Vec3> nodes, int reach) const = 0;
  /// Re-reads the fluid's state after it changed outside step() (a checkpoint restored). Collective.
  virtual void refresh() {}
  /// Whether stokes_response() is available (the semi-implicit coupling's fluid model).
  virtual bool has_stokes_response() const { return false; }
  /// The velocity (a local vector of grid()) one step of dt gives the body force `force` (a local
  /// vector of grid()) from rest, with homogeneous boundary data and no convection. Collective.
  virtual void stokes_response(Vec /*force*/, double /*dt*/, Vec /*velocity*/) {}
  /// Adds a stokes_response() (velocity and pressure) to the fluid's state after a step. Collective.
  virtual void add_to_state(Vec /*increment*/) {}
};

/// The IB's view of either flow solver: a UniformFluid of a fluid::NavierStokes, a NestedFluid of a
/// fluid::NestedNavierStokes (whose u^n it copies at once). `fluid` must outlive the view.
std::unique_ptr<EulerianFluid> make_eulerian_fluid(fluid::FlowSolver& fluid);

/// fluid::NavierStokes as it is: grid(), state() and body_force() used in place.
class UniformFluid final : public EulerianFluid {
 public:
  explicit UniformFluid(fluid::NavierStokes& fluid) : fluid_(fluid) {}

  const fluid::StaggeredGrid& grid() const override;
  Vec velocity() const override;
  Vec force() override;
  void apply_force() override {} // the spreading wrote the body force itself
  void step(double dt) override;
  double time() const override;
  double last_step() const override;
  double density() const override;
  double viscosity() const override;
  void require_inside(std::span<const Vec3>, int) const override {}
  bool has_stokes_response() const override { return true; }
  void stokes_response(Vec force, double dt, Vec velocity) override;
  void add_to_state(Vec increment) override;

  fluid::NavierStokes& navier_stokes() const { return fluid_; }

 private:
  fluid::NavierStokes& fluid_;
};

/// fluid::NestedNavierStokes with the structure on its finest level (which must be one box).
class NestedFluid final : public EulerianFluid {
 public:
  /// Copies the fluid's current u^n to the finest level: construct after its initial condition is set
  /// (or call copy_velocity() after changing the state outside step()).
  explicit NestedFluid(fluid::NestedNavierStokes& fluid);
  NestedFluid(const NestedFluid&) = delete;
  NestedFluid& operator=(const NestedFluid&) = delete;

  const fluid::StaggeredGrid& grid() const override;
  /// The finest level's local vector: faces u^n, owned cells p^{n-1/2} (composite values).
  Vec velocity() const override { return velocity_.get(); }
  Vec force() override;
  void apply_force() override;
  void step(double dt) override;
  double time() const override;
  double last_step() const override;
  double density() const override;
  double viscosity() const override;
  /// RunError naming the first node (by index) outside the finest level's box less `reach` cells, the
  /// box and the time. Sides of the box on the domain's sides are not checked (the boundary is met as on
  /// one grid).
  void require_inside(std::span<const Vec3> nodes, int reach) const override;
  void refresh() override { copy_velocity(); }

  void copy_velocity();
  fluid::NestedNavierStokes& navier_stokes() const { return fluid_; }

 private:
  fluid::NestedNavierStokes& fluid_;
  petsc::OwnedVec velocity_, force_;
};

} // namespace ibvalve::ib
