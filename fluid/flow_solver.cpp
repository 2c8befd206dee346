#include "fluid/flow_solver.hpp"

#include <memory>

#include "fluid/navier_stokes.hpp"
#include "fluid/nested_navier_stokes.hpp"

namespace ibvalve::fluid {

std::unique_ptr<FlowSolver> make_flow_solver(MPI_Comm comm, const BoxGeometry& box,
                                             const GridHierarchy* levels, BoundaryConditions bc,
                                             const FluidSettings& settings)
{
  if (levels) return std::make_unique<NestedNavierStokes>(comm, *levels, std::move(bc), settings);
  return std::make_unique<NavierStokes>(comm, box, std::move(bc), settings);
}

} // namespace ibvalve::fluid
