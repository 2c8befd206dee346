#include "app/ibfe_nested_run.hpp"

#include <algorithm>
#include <array>
#include <sstream>
#include <string>

#include <mpi.h>

#include "app/ibfe_fields.hpp"
#include "app/ibfe_run_loop.hpp"
#include "ib/eulerian_fluid.hpp"
#include "io/logger.hpp"
#include "io/petsc_check.hpp"
#include "io/petsc_handle.hpp"

namespace ibvalve::app {

namespace {

// 1/2 rho sum_f W_f u_f^2 over the composite faces (W_f the face weights of the composite operators:
// each face's share of the volume, h^3 on one level).
double composite_kinetic_energy(const fluid::NestedNavierStokes& fluid)
{
  petsc::OwnedVec squared;
  PETSC_CHECK(VecDuplicate(fluid.velocity(), squared.out()));
  PETSC_CHECK(VecPointwiseMult(squared, fluid.velocity(), fluid.velocity()));
  double sum = 0.0;
  PETSC_CHECK(VecDot(squared, fluid.operators().weights(), &sum));
  return 0.5 * fluid.settings().rho * sum;
}

} // namespace

double composite_cells(const fluid::GridHierarchy& hierarchy)
{
  double cells = 1.0;
  for (int d = 0; d < 3; ++d) cells *= static_cast<double>(hierarchy.domain_cells(0)[d]);
  for (int level = 1; level < hierarchy.levels(); ++level)
    for (const fluid::IndexBox& box : hierarchy.boxes(level))
      cells += static_cast<double>(box.cells(0)) * static_cast<double>(box.cells(1)) *
               static_cast<double>(box.cells(2));
  return cells;
}

fluid::GridHierarchy read_structure_levels(const io::Config& config, const fluid::BoxGeometry& box,
                                           std::span<const fe::Vec3> positions, ib::KernelKind kernel,
                                           const std::string& structure_key)
{
  fluid::PhysicalBox bounds;
  for (int d = 0; d < 3; ++d) {
    bounds.lower[d] = 1e300;
    bounds.upper[d] = -1e300;
  }
  for (const fe::Vec3& x : positions)
    for (int d = 0; d < 3; ++d) {
      bounds.lower[d] = std::min(bounds.lower[d], x[d]);
      bounds.upper[d] = std::max(bounds.upper[d], x[d]);
    }
  const int reach = (ib::DeltaKernel(kernel).support() + 1) / 2;
  fluid::GridHierarchy hierarchy = fluid::read_hierarchy(config, box, bounds, structure_key, reach);
  if (hierarchy.boxes(hierarchy.finest()).size() != 1)
    config.fail("nested.box", "the finest level must be one box: the structure lives on it");
  return hierarchy;
}

RunSummary run_ibfe_on_nested_levels(const RunContext& context, const NestedIbfeCase& c)
{
  auto& log = io::Logger::global();
  const fluid::GridHierarchy& hierarchy = *c.hierarchy;
  fluid::NestedNavierStokes fluid(context.comm, hierarchy, fluid::VelocityFunction{}, c.fluid);
  fluid.set_initial_condition(
      [](const fluid::Real3&, double) {
        return fluid::Real3{0.0, 0.0, 0.0};
      },
      [](const fluid::Real3&, double) { return 0.0; }, 0.0);
  ib::NestedFluid finest(fluid);
  fe::SolidModel solid(*c.mesh, *c.parts, c.quadrature_degree, context.comm);
  solid.set_fibers(*c.fibers);
  ib::IbfeIntegrator ibfe(finest, solid, c.ib);
  ibfe.set_displacement(c.initial_displacement);
  {
    std::ostringstream s;
    s.precision(4);
    PetscInt cells = 0;
    for (int l = 0; l < hierarchy.levels(); ++l) cells += hierarchy.uncovered_cells(l);
    const fluid::BoxGeometry& box = finest.grid().box();
    s << "nested levels: " << hierarchy.levels() << " levels, " << cells
      << " composite cells; the structure on "
      << "level " << hierarchy.finest() << " (spacing " << finest.grid().h(0) << " cm, box [" << box.lower[0]
      << ", " << box.upper[0] << "] x [" << box.lower[1] << ", " << box.upper[1] << "] x [" << box.lower[2]
      << ", " << box.upper[2] << "] cm)";
    log.info(s.str());
  }
  log.info("structure: " + std::to_string(c.mesh->num_elements()) + " elements, " +
           std::to_string(c.mesh->num_nodes()) + " nodes, volume " + std::to_string(c.mesh->volume()) +
           " cm^3");

  IbfeFluidHooks hooks;
  hooks.kinetic_energy = [&] { return composite_kinetic_energy(fluid); };
  hooks.write_fields = [&](io::XdmfTimeSeries& series, long step) {
    write_ibfe_fields(context.comm, context.run_directory, series, *c.mesh, fluid, ibfe, step);
  };
  hooks.save = [&](io::Hdf5File& h5) { fluid.save(h5, "nested_fluid"); };
  hooks.restore = [&](const io::Hdf5File& h5) {
    fluid.restore(h5, "nested_fluid");
    finest.copy_velocity();
  };
  hooks.solver_summary = [&] {
    return "; fluid iterations: velocity " + std::to_string(fluid.statistics().velocity_iterations) +
           ", pressure " + std::to_string(fluid.statistics().pressure_iterations);
  };
  hooks.step_figures = [&](double dt) { return fluid_step_figures(fluid, dt); };
  return run_ibfe_loop(context, ibfe, *c.mesh, {c.end, c.dt, c.output_every, c.checkpoints}, hooks);
}

} // namespace ibvalve::app
