#include "ib/eulerian_fluid.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "base/errors.hpp"
#include "fluid/navier_stokes.hpp"
#include "fluid/nested_navier_stokes.hpp"
#include "io/petsc_check.hpp"

namespace ibvalve::ib {

std::unique_ptr<EulerianFluid> make_eulerian_fluid(fluid::FlowSolver& fluid)
{
  if (auto* uniform = dynamic_cast<fluid::NavierStokes*>(&fluid))
    return std::make_unique<UniformFluid>(*uniform);
  if (auto* nested = dynamic_cast<fluid::NestedNavierStokes*>(&fluid))
    return std::make_unique<NestedFluid>(*nested);
  throw std::invalid_argument("ib: no IB view of this flow solver");
}

const fluid::StaggeredGrid& UniformFluid::grid() const
{
  return fluid_.grid();
}
Vec UniformFluid::velocity() const
{
  return fluid_.state();
}
Vec UniformFluid::force()
{
  return fluid_.body_force();
}
void UniformFluid::step(double dt)
{
  fluid_.step(dt);
}
void UniformFluid::stokes_response(Vec force, double dt, Vec velocity)
{
  fluid_.stokes_response(force, dt, velocity);
}
void UniformFluid::add_to_state(Vec increment)
{
  fluid_.add_to_state(increment);
}
double UniformFluid::time() const
{
  return fluid_.time();
}
double UniformFluid::last_step() const
{
  return fluid_.last_step();
}
double UniformFluid::density() const
{
  return fluid_.settings().rho;
}
double UniformFluid::viscosity() const
{
  return fluid_.settings().mu;
}

NestedFluid::NestedFluid(fluid::NestedNavierStokes& fluid) : fluid_(fluid)
{
  velocity_ = grid().create_local();
  force_ = grid().create_local();
  copy_velocity();
}

const fluid::StaggeredGrid& NestedFluid::grid() const
{
  return fluid_.finest_level_grid();
}

Vec NestedFluid::force()
{
  // Zeroed so that no slot keeps an earlier step's force (the spreading overwrites the owned faces).
  PETSC_CHECK(VecZeroEntries(force_));
  return force_;
}

void NestedFluid::apply_force()
{
  // The structure is the only body force of a coupled run: f^{n+1/2} is the spread force alone.
  PETSC_CHECK(VecZeroEntries(fluid_.body_force()));
  fluid_.add_force_from_finest(force_);
}

void NestedFluid::step(double dt)
{
  fluid_.step(dt);
  copy_velocity();
}

void NestedFluid::copy_velocity()
{
  fluid_.velocity_to_finest(velocity_);
}
double NestedFluid::time() const
{
  return fluid_.time();
}
double NestedFluid::last_step() const
{
  return fluid_.last_step();
}
double NestedFluid::density() const
{
  return fluid_.settings().rho;
}
double NestedFluid::viscosity() const
{
  return fluid_.settings().mu;
}

void NestedFluid::require_inside(std::span<const Vec3> nodes, int reach) const
{
  const fluid::BoxGeometry& box = grid().box();
  const fluid::BoxGeometry& domain = fluid_.hierarchy().domain();
  for (std::size_t n = 0; n < nodes.size(); ++n)
    for (int d = 0; d < 3; ++d) {
      // A side of the finest box on the domain's side is no edge of the level: the kernel meets the
      // boundary there as on one grid (a vessel's end beside an open side).
      const double tolerance = 1e-9 * domain.length(d);
      const double room = reach * grid().h(d);
      const double lower =
          std::abs(box.lower[d] - domain.lower[d]) < tolerance ? -1e300 : box.lower[d] + room;
      const double upper = std::abs(box.upper[d] - domain.upper[d]) < tolerance ? 1e300 : box.upper[d] - room;
      if (!(nodes[n][d] >= lower && nodes[n][d] <= upper)) {
        std::ostringstream msg;
        msg << "ib: structure node " << n << " at (" << nodes[n][0] << ", " << nodes[n][1] << ", "
            << nodes[n][2] << ") cm left the finest grid level (level " << fluid_.hierarchy().finest()
            << ", [" << box.lower[0] << ", " << box.upper[0] << "] x [" << box.lower[1] << ", "
            << box.upper[1] << "] x [" << box.lower[2] << ", " << box.upper[2]
            << "] cm, less the kernel's reach of " << reach << " cells) at t = " << fluid_.time()
            << " s; the immersed boundary lives on the finest level only: enlarge it (nested.margins or "
               "its [[nested.box]])";
        throw RunError(msg.str());
      }
    }
}

} // namespace ibvalve::ib
